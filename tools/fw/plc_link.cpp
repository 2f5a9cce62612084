#include "plc_link.hpp"

#include <cstdio>
#include <stdexcept>

#if DYNWEIGH_HAS_MODBUS
#include "dynweigh/modbus/modbus_server.hpp"
#endif

namespace dynweigh::tools {

void JiffyStopwatch::stop() {
  const double us =
      std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - started_).count();
  ++jiffies_;
  total_us_ += us;
  if (us > worst_us_) worst_us_ = us;
}

PlcLink::PlcLink(const std::vector<modbus::Endpoint>& endpoints) {
#if DYNWEIGH_HAS_MODBUS
  for (const modbus::Endpoint& endpoint : endpoints) {
    servers_.push_back(std::make_unique<modbus::ModbusServer>(endpoint, mailbox_));
    std::fprintf(stderr, "dynweigh-fw: modbus: serving %s\n", endpoint.text.c_str());
  }
#else
  if (!endpoints.empty()) throw std::runtime_error("--modbus: this build has no libmodbus");
#endif
}

PlcLink::~PlcLink() {
  if (!active()) return;
  servers_.clear();  // no request after this line
  std::fprintf(stderr, "modbus_requests=%u\nplc_watchdog_aborted=%d\n", console_ ? console_->requests() : 0u,
               console_ && console_->watchdog_fired() ? 1 : 0);
  std::fprintf(stderr, "loop_jiffies=%llu\nloop_jiffy_worst_us=%.0f\nloop_jiffy_mean_us=%.1f\n",
               static_cast<unsigned long long>(stopwatch_.jiffies()), stopwatch_.worst_us(), stopwatch_.mean_us());
}

hal::ConsolePort& PlcLink::attach(hal::ConsolePort& operator_console) {
  if (!active()) return operator_console;
  console_ = std::make_unique<modbus::PlcConsole>(operator_console, mailbox_);
  return *console_;
}

std::vector<modbus::Endpoint> parse_modbus_options(const std::vector<std::string>& options) {
  std::vector<modbus::Endpoint> endpoints;
  for (const std::string& text : options) {
    std::string error;
    const auto endpoint = modbus::parse_endpoint(text, error);
    if (!endpoint) throw std::runtime_error(error);
    endpoints.push_back(*endpoint);
  }
  return endpoints;
}

}  // namespace dynweigh::tools
