#include "dynweigh/hal/host/pty_console.hpp"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <stdexcept>


namespace dynweigh::hal::host {

PtyConsole::PtyConsole() {
  master_ = posix_openpt(O_RDWR | O_NOCTTY);
  if (master_ < 0 || grantpt(master_) != 0 || unlockpt(master_) != 0) {
    throw std::runtime_error("cannot open a pseudo-terminal");
  }
  const char* name = ptsname(master_);
  if (!name) throw std::runtime_error("cannot name the pseudo-terminal");
  path_ = name;
  slave_ = ::open(name, O_RDWR | O_NOCTTY);
  if (slave_ < 0) throw std::runtime_error("cannot open " + path_);
  termios tio{};
  tcgetattr(slave_, &tio);
  cfmakeraw(&tio);
  cfsetispeed(&tio, B115200);
  cfsetospeed(&tio, B115200);
  tcsetattr(slave_, TCSANOW, &tio);
  fcntl(master_, F_SETFL, fcntl(master_, F_GETFL) | O_NONBLOCK);
}

PtyConsole::~PtyConsole() {
  if (slave_ >= 0) ::close(slave_);
  if (master_ >= 0) ::close(master_);
}

bool PtyConsole::wait_for_input(int timeout_ms) const {
  pollfd fd{master_, POLLIN, 0};
  return ::poll(&fd, 1, timeout_ms) > 0 && (fd.revents & POLLIN);
}

std::size_t PtyConsole::read(char* destination, std::size_t capacity) {
  output_.flush(master_);  // once a jiffy: what the line took since
  const ssize_t n = ::read(master_, destination, capacity);
  return n > 0 ? std::size_t(n) : 0;
}

void PtyConsole::write(const char* data, std::size_t length) { output_.write(master_, data, length); }

}  // namespace dynweigh::hal::host
