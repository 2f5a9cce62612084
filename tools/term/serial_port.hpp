#pragma once
// A serial device or pty opened the way an indicator's console expects: raw (no echo, no line
// discipline, no CR/LF translation), 8 data bits, no parity, 1 stop bit, no flow control.
#include <cstddef>
#include <string>

namespace dynweigh::tools {

class SerialPort {
 public:
  // Throws std::runtime_error (one line) if the device cannot be opened or the baud rate is not
  // one termios knows.
  SerialPort(const std::string& device, unsigned baud);
  ~SerialPort();
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  int fd() const { return fd_; }
  // Waits up to `timeout_ms` for bytes; returns how many were read (0: none came). Throws if the
  // device went away.
  std::size_t read(char* destination, std::size_t capacity, int timeout_ms);
  void write(const std::string& bytes);
  // Drops what arrived before we started listening (a previous session's tail).
  void discard_input();

 private:
  int fd_ = -1;
  std::string device_;
};

}  // namespace dynweigh::tools
