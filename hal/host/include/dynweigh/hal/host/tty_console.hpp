#pragma once
// The console on an existing serial device (a UART's /dev/ttyS1, a USB adapter's /dev/ttyUSB0, or
// one end of a pty pair): raw mode, 8N1, non-blocking.
#include <string>

#include "dynweigh/hal/host/serial_line_console.hpp"

namespace dynweigh::hal::host {

class TtyConsole final : public SerialLineConsole {
 public:
  explicit TtyConsole(const std::string& device, int baud = 115200);  // throws std::runtime_error
};

}  // namespace dynweigh::hal::host
