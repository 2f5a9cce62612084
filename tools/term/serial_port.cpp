#include "serial_port.hpp"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace dynweigh::tools {
namespace {

speed_t speed_of(unsigned baud) {
  switch (baud) {
    case 1200: return B1200;
    case 2400: return B2400;
    case 4800: return B4800;
    case 9600: return B9600;
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    case 230400: return B230400;
    case 460800: return B460800;
    case 921600: return B921600;
    default: throw std::runtime_error("--baud " + std::to_string(baud) + " is not a standard rate (9600 ... 921600)");
  }
}

}  // namespace

SerialPort::SerialPort(const std::string& device, unsigned baud) : device_(device) {
  const speed_t speed = speed_of(baud);
  fd_ = ::open(device.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error("cannot open " + device + ": " + std::strerror(errno));
  termios tio{};
  if (::tcgetattr(fd_, &tio) != 0) {
    ::close(fd_);
    throw std::runtime_error(device + " is not a serial device or pty");
  }
  ::cfmakeraw(&tio);
  tio.c_cflag &= ~tcflag_t(CSIZE | PARENB | CSTOPB | CRTSCTS);
  tio.c_cflag |= CS8 | CLOCAL | CREAD;  // 8N1, ignore modem lines
  tio.c_iflag &= ~tcflag_t(IXON | IXOFF | IXANY);
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  ::cfsetispeed(&tio, speed);
  ::cfsetospeed(&tio, speed);
  if (::tcsetattr(fd_, TCSANOW, &tio) != 0) {
    ::close(fd_);
    throw std::runtime_error("cannot configure " + device + ": " + std::strerror(errno));
  }
}

SerialPort::~SerialPort() {
  if (fd_ >= 0) ::close(fd_);
}

std::size_t SerialPort::read(char* destination, std::size_t capacity, int timeout_ms) {
  pollfd p{fd_, POLLIN, 0};
  const int ready = ::poll(&p, 1, timeout_ms);
  if (ready < 0) {
    if (errno == EINTR) return 0;
    throw std::runtime_error(device_ + ": " + std::strerror(errno));
  }
  if (ready == 0) return 0;
  const ssize_t n = ::read(fd_, destination, capacity);
  if (n > 0) return std::size_t(n);
  if (n < 0 && (errno == EAGAIN || errno == EINTR)) return 0;
  if (p.revents & (POLLHUP | POLLERR) || n == 0 || n < 0) throw std::runtime_error(device_ + ": the device went away");
  return 0;
}

void SerialPort::write(const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n > 0) {
      done += std::size_t(n);
      continue;
    }
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) {
      pollfd p{fd_, POLLOUT, 0};
      if (::poll(&p, 1, 2000) <= 0) throw std::runtime_error(device_ + ": nobody reads (write timed out)");
      continue;
    }
    throw std::runtime_error(device_ + ": write failed: " + std::strerror(errno));
  }
}

void SerialPort::discard_input() {
  ::tcflush(fd_, TCIFLUSH);
  char sink[256];
  while (::read(fd_, sink, sizeof sink) > 0) {
  }
}

}  // namespace dynweigh::tools
