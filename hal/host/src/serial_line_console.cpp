#include "dynweigh/hal/host/serial_line_console.hpp"

#include <poll.h>
#include <unistd.h>

namespace dynweigh::hal::host {

SerialLineConsole::~SerialLineConsole() {
  if (fd_ >= 0) ::close(fd_);
}

bool SerialLineConsole::wait_for_input(int timeout_ms) const {
  pollfd fd{fd_, POLLIN, 0};
  return ::poll(&fd, 1, timeout_ms) > 0 && (fd.revents & POLLIN);
}

std::size_t SerialLineConsole::read(char* destination, std::size_t capacity) {
  output_.flush(fd_);  // once a jiffy: what the line took since
  const ssize_t n = ::read(fd_, destination, capacity);
  return n > 0 ? std::size_t(n) : 0;
}

void SerialLineConsole::write(const char* data, std::size_t length) { output_.write(fd_, data, length); }

}  // namespace dynweigh::hal::host
