#include "dynweigh/hal/host/pty_console.hpp"

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace dynweigh::hal::host {

PtyConsole::PtyConsole() {
  const int master = posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0) throw std::runtime_error("cannot open a pseudo-terminal");
  adopt_line(master, "");  // closed with the console from here on
  if (grantpt(master) != 0 || unlockpt(master) != 0) throw std::runtime_error("cannot open a pseudo-terminal");
  const char* name = ptsname(master);
  if (!name) throw std::runtime_error("cannot name the pseudo-terminal");
  adopt_line(master, name);
  slave_ = ::open(name, O_RDWR | O_NOCTTY);
  if (slave_ < 0) throw std::runtime_error("cannot open " + device_path());
  termios tio{};
  tcgetattr(slave_, &tio);
  cfmakeraw(&tio);
  cfsetispeed(&tio, B115200);
  cfsetospeed(&tio, B115200);
  tcsetattr(slave_, TCSANOW, &tio);
  fcntl(master, F_SETFL, fcntl(master, F_GETFL) | O_NONBLOCK);
}

PtyConsole::~PtyConsole() {
  if (slave_ >= 0) ::close(slave_);
}

}  // namespace dynweigh::hal::host
