#include "dynweigh/hal/host/tty_console.hpp"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>


namespace dynweigh::hal::host {
namespace {
speed_t speed_for(int baud) {
  switch (baud) {
    case 9600: return B9600;
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    case 230400: return B230400;
    default: throw std::runtime_error("unsupported baud rate " + std::to_string(baud));
  }
}
}  // namespace

TtyConsole::TtyConsole(const std::string& device, int baud) : path_(device) {
  fd_ = ::open(device.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (fd_ < 0) throw std::runtime_error("cannot open " + device + ": " + std::strerror(errno));
  termios tio{};
  if (tcgetattr(fd_, &tio) != 0) {
    ::close(fd_);
    throw std::runtime_error(device + " is not a terminal");
  }
  cfmakeraw(&tio);
  tio.c_cflag |= CLOCAL | CREAD;  // 8N1 without modem control
  cfsetispeed(&tio, speed_for(baud));
  cfsetospeed(&tio, speed_for(baud));
  tcsetattr(fd_, TCSANOW, &tio);
}

TtyConsole::~TtyConsole() {
  if (fd_ >= 0) ::close(fd_);
}

bool TtyConsole::wait_for_input(int timeout_ms) const {
  pollfd fd{fd_, POLLIN, 0};
  return ::poll(&fd, 1, timeout_ms) > 0 && (fd.revents & POLLIN);
}

std::size_t TtyConsole::read(char* destination, std::size_t capacity) {
  output_.flush(fd_);  // once a jiffy: what the line took since
  const ssize_t n = ::read(fd_, destination, capacity);
  return n > 0 ? std::size_t(n) : 0;
}

void TtyConsole::write(const char* data, std::size_t length) { output_.write(fd_, data, length); }

}  // namespace dynweigh::hal::host
