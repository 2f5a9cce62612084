#pragma once
// A Modbus server (libmodbus) on its own thread: TCP with any number of clients up to a limit, or
// RTU on a serial line. Requests are decoded by the PlcMailbox's register map; the control loop is
// never waited for. A slow, silent or broken client costs this thread time, never the loop's.
#include <atomic>
#include <memory>
#include <thread>

#include "dynweigh/modbus/endpoint.hpp"
#include "dynweigh/modbus/plc_mailbox.hpp"

namespace dynweigh::modbus {

class ModbusServer {
 public:
  // Binds or opens the endpoint now (throws std::runtime_error with a one-line reason), then
  // serves it on a thread until destroyed.
  ModbusServer(const Endpoint& endpoint, PlcMailbox& mailbox);
  ~ModbusServer();
  ModbusServer(const ModbusServer&) = delete;
  ModbusServer& operator=(const ModbusServer&) = delete;

  // Open TCP connections beyond this are closed as they come.
  static constexpr int kMaxTcpClients = 200;
  // A frame that stops arriving is dropped after this long between two of its bytes.
  static constexpr int kByteTimeoutMs = 200;

 private:
  struct Context;
  void serve_tcp();
  void serve_rtu();
  void answer(int header_length, int trailer_length, const std::uint8_t* query, int length);

  PlcMailbox& mailbox_;
  std::unique_ptr<Context> context_;
  std::atomic<bool> stopping_{false};
  int stop_pipe_[2] = {-1, -1};
  std::thread thread_;
};

}  // namespace dynweigh::modbus
