#pragma once
// What the pty and the tty console share once their line is open: a non-blocking descriptor, read
// once a jiffy, written through SerialOutput (answers end in CR LF; never waits for the reader).
#include <string>

#include "dynweigh/hal/host/serial_output.hpp"
#include "dynweigh/hal/ports.hpp"

namespace dynweigh::hal::host {

class SerialLineConsole : public ConsolePort {
 public:
  ~SerialLineConsole() override;
  SerialLineConsole(const SerialLineConsole&) = delete;
  SerialLineConsole& operator=(const SerialLineConsole&) = delete;

  const std::string& device_path() const { return path_; }
  // Waits up to `timeout_ms` for input; true if some is ready.
  bool wait_for_input(int timeout_ms) const;

  std::size_t read(char* destination, std::size_t capacity) override;
  void write(const char* data, std::size_t length) override;
  std::size_t writable() const override { return output_.writable(); }

 protected:
  SerialLineConsole() = default;
  // Takes `fd` (closed with the console) and the device path users are told to open.
  void adopt_line(int fd, const std::string& path) {
    fd_ = fd;
    path_ = path;
  }

 private:
  SerialOutput output_;
  int fd_ = -1;
  std::string path_;
};

}  // namespace dynweigh::hal::host
