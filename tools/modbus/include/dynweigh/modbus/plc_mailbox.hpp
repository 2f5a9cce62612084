#pragma once
// Where the Modbus servers' threads and the control loop meet. A server thread may wait for the
// lock (it holds it only to decode one request); the control loop never waits: it tries the lock
// once a jiffy and, when a server holds it, publishes and collects in the next jiffy instead.
#include <cstdint>
#include <mutex>

#include "dynweigh/modbus/register_map.hpp"

namespace dynweigh::modbus {

class PlcMailbox {
 public:
  // Server side: one request's PDU, decoded against the loop's last snapshot; a command it writes
  // waits here for the loop (an abort replaces a command the loop has not taken yet).
  RegisterMap::Outcome serve(const std::uint8_t* pdu, std::size_t length, std::uint16_t* registers,
                             std::size_t* register_count);

  // Loop side, never blocking. Publishes `snapshot`; when the loop can run a command now
  // (`take_any`, or `take_abort` for an abort), moves the waiting one to `taken`. Returns false,
  // having done nothing, when a server holds the lock.
  struct Exchange {
    bool taken = false;
    CommandRequest command;
    std::uint32_t requests = 0;  // requests served since start (wraps)
  };
  bool try_exchange(const LoopSnapshot& snapshot, bool take_any, bool take_abort, Exchange& exchange);

  // A command waits for the loop (true too when a server holds the lock: ask again next time).
  bool command_waiting() {
    const std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
    return !lock.owns_lock() || waiting_;
  }

  std::uint32_t requests() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return requests_;
  }

 private:
  std::mutex mutex_;
  RegisterMap map_;
  LoopSnapshot snapshot_;
  bool waiting_ = false;
  CommandRequest waiting_command_;
  std::uint32_t requests_ = 0;
};

}  // namespace dynweigh::modbus
