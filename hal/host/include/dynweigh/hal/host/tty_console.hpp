#pragma once
// The console on an existing serial device (a UART's /dev/ttyS1, a USB adapter's /dev/ttyUSB0, or
// one end of a pty pair): raw mode, 8N1, non-blocking.
#include <string>

#include "dynweigh/hal/host/serial_output.hpp"
#include "dynweigh/hal/ports.hpp"

namespace dynweigh::hal::host {

class TtyConsole final : public ConsolePort {
 public:
  explicit TtyConsole(const std::string& device, int baud = 115200);  // throws std::runtime_error
  ~TtyConsole() override;
  TtyConsole(const TtyConsole&) = delete;
  TtyConsole& operator=(const TtyConsole&) = delete;

  const std::string& device_path() const { return path_; }
  bool wait_for_input(int timeout_ms) const;
  std::size_t read(char* destination, std::size_t capacity) override;
  // Answers end in CR LF on a serial line; never waits for the reader (serial_output.hpp).
  void write(const char* data, std::size_t length) override;
  std::size_t writable() const override { return output_.writable(); }

 private:
  SerialOutput output_;
  int fd_ = -1;
  std::string path_;
};

}  // namespace dynweigh::hal::host
