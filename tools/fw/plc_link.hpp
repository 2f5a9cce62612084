#pragma once
// dynweigh-fw --modbus: the Modbus servers, the mailbox they share with the control loop, and how
// long the loop's jiffies took (printed as key=value lines on stderr at exit).
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "dynweigh/hal/ports.hpp"
#include "dynweigh/modbus/endpoint.hpp"
#include "dynweigh/modbus/plc_console.hpp"
#include "dynweigh/modbus/plc_mailbox.hpp"

namespace dynweigh::modbus {
class ModbusServer;
}

namespace dynweigh::tools {

// The work of one jiffy (step, console, registers, trace), without the wait for the next.
class JiffyStopwatch {
 public:
  void start() { started_ = std::chrono::steady_clock::now(); }
  void stop();
  std::uint64_t jiffies() const { return jiffies_; }
  double worst_us() const { return worst_us_; }
  double mean_us() const { return jiffies_ ? total_us_ / double(jiffies_) : 0.0; }

 private:
  std::chrono::steady_clock::time_point started_;
  std::uint64_t jiffies_ = 0;
  double worst_us_ = 0.0;
  double total_us_ = 0.0;
};

class PlcLink {
 public:
  // Opens every endpoint now (throws std::runtime_error with a one-line reason); none: inactive.
  explicit PlcLink(const std::vector<modbus::Endpoint>& endpoints);
  ~PlcLink();
  PlcLink(const PlcLink&) = delete;
  PlcLink& operator=(const PlcLink&) = delete;

  bool active() const { return !servers_.empty(); }
  // The console port the board should use: the operator's console with the PLC's commands beside it.
  hal::ConsolePort& attach(hal::ConsolePort& operator_console);
  void before_jiffy() {
    if (console_) console_->before_jiffy();
  }
  bool command_waiting() { return console_ && console_->command_waiting(); }
  // After every jiffy, with the board's outputs.
  void after_jiffy(const firmware::Indicator& indicator, const firmware::Outputs& outputs) {
    if (console_) console_->after_jiffy(indicator, outputs);
  }
  JiffyStopwatch& stopwatch() { return stopwatch_; }

 private:
  modbus::PlcMailbox mailbox_;
  std::vector<std::unique_ptr<modbus::ModbusServer>> servers_;
  std::unique_ptr<modbus::PlcConsole> console_;
  JiffyStopwatch stopwatch_;
};

// Every --modbus value parsed; throws std::runtime_error naming the bad one.
std::vector<modbus::Endpoint> parse_modbus_options(const std::vector<std::string>& options);

}  // namespace dynweigh::tools
