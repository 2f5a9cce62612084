#include "dynweigh/hal/host/tty_console.hpp"

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>

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

TtyConsole::TtyConsole(const std::string& device, int baud) {
  const int fd = ::open(device.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (fd < 0) throw std::runtime_error("cannot open " + device + ": " + std::strerror(errno));
  adopt_line(fd, device);
  termios tio{};
  if (tcgetattr(fd, &tio) != 0) throw std::runtime_error(device + " is not a terminal");
  cfmakeraw(&tio);
  tio.c_cflag |= CLOCAL | CREAD;  // 8N1 without modem control
  cfsetispeed(&tio, speed_for(baud));
  cfsetospeed(&tio, speed_for(baud));
  tcsetattr(fd, TCSANOW, &tio);
}

}  // namespace dynweigh::hal::host
