#pragma once
// The console on a pseudo-terminal, so `screen`, `minicom` or pyserial reach the host build as
// they would a UART. Raw mode, non-blocking.
#include "dynweigh/hal/host/serial_line_console.hpp"

namespace dynweigh::hal::host {

class PtyConsole final : public SerialLineConsole {
 public:
  PtyConsole();  // throws std::runtime_error if no pty can be had
  ~PtyConsole() override;

 private:
  int slave_ = -1;  // kept open so the master never sees a hang-up between clients
};

}  // namespace dynweigh::hal::host
