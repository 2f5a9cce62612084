#pragma once
// The transmit side of a console on a serial line or pty: a fixed ring the board fills and a
// non-blocking writer empties as fast as the line (or the program at the other end) takes it, so
// the control loop never waits for a reader; what does not fit stays in the indicator's ring
// (ConsolePort::writable). A line in raw mode has no output processing, and a bare LF moves a
// terminal (picocom, screen, minicom) down without returning it to column 0: each '\n' goes out as
// CR LF, as on a UART. stdio keeps LF.
#include <cstddef>

namespace dynweigh::hal::host {

class SerialOutput {
 public:
  // Holds a whole `readtestdata` (about 20 KB) and more: a recording board (--record), which drains
  // the indicator fully every jiffy as a replay does, loses nothing to a reader a little behind.
  static constexpr std::size_t kCapacity = 65536;

  // Bytes of the indicator's text that fit now (each may become two).
  std::size_t writable() const { return (kCapacity - size_) / 2; }
  // Queues `data` (at most writable() bytes are kept) and writes what the descriptor takes now.
  void write(int fd, const char* data, std::size_t length);
  // Writes what the descriptor takes now; never waits.
  void flush(int fd);

 private:
  void push(char c) {
    ring_[(head_ + size_) % kCapacity] = c;
    ++size_;
  }
  char ring_[kCapacity] = {};
  std::size_t head_ = 0, size_ = 0;
};

}  // namespace dynweigh::hal::host
