#pragma once
// The console on a pseudo-terminal, so `screen`, `minicom` or pyserial reach the host build as
// they would a UART. Raw mode, non-blocking.
#include <string>

#include "dynweigh/hal/host/serial_output.hpp"
#include "dynweigh/hal/ports.hpp"

namespace dynweigh::hal::host {

class PtyConsole final : public ConsolePort {
 public:
  PtyConsole();  // throws std::runtime_error if no pty can be had
  ~PtyConsole() override;
  PtyConsole(const PtyConsole&) = delete;
  PtyConsole& operator=(const PtyConsole&) = delete;

  const std::string& device_path() const { return path_; }
  // Waits up to `timeout_ms` for input; true if some is ready.
  bool wait_for_input(int timeout_ms) const;

  std::size_t read(char* destination, std::size_t capacity) override;
  // Answers end in CR LF on a serial line; never waits for the reader (serial_output.hpp).
  void write(const char* data, std::size_t length) override;
  std::size_t writable() const override { return output_.writable(); }

 private:
  SerialOutput output_;
  int master_ = -1;
  int slave_ = -1;  // kept open so the master never sees a hang-up between clients
  std::string path_;
};

}  // namespace dynweigh::hal::host
