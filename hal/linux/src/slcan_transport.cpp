// The slcan transport (docs/can-protocol.md): Lawicel ASCII on a serial line, a pty, or a unix-domain socket (QEMU's
// `-chardev socket,path=P,server=on`, so a board in QEMU is reached without a pty in between).
#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "dynweigh/hal/can/slcan.hpp"
#include "dynweigh/hal/linux/can_transport.hpp"

namespace dynweigh::hal::linux_can {
namespace {

int open_unix_socket(const std::string& path) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) throw std::runtime_error("slcan: cannot create a socket: " + std::string(std::strerror(errno)));
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path.size() >= sizeof address.sun_path) {
    ::close(fd);
    throw std::invalid_argument("slcan: socket path too long: " + path);
  }
  std::strncpy(address.sun_path, path.c_str(), sizeof address.sun_path - 1);
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    const std::string reason = std::strerror(errno);
    ::close(fd);
    throw std::runtime_error("slcan: cannot connect to " + path + ": " + reason);
  }
  return fd;
}

int open_serial(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error("slcan: cannot open " + path + ": " + std::strerror(errno));
  termios tio{};
  if (::tcgetattr(fd, &tio) == 0) {  // a tty or pty: raw, 8N1; a plain file or fifo is fine too
    ::cfmakeraw(&tio);
    ::cfsetispeed(&tio, B115200);
    ::cfsetospeed(&tio, B115200);
    tio.c_cflag |= CLOCAL | CREAD;
    ::tcsetattr(fd, TCSANOW, &tio);
  }
  return fd;
}

class SlcanTransport final : public CanTransport {
 public:
  explicit SlcanTransport(const std::string& device) : name_("slcan:" + device) {
    struct stat info {};
    if (::stat(device.c_str(), &info) != 0) {
      throw std::runtime_error("slcan: no device " + device + ": " + std::strerror(errno));
    }
    socket_ = S_ISSOCK(info.st_mode);
    fd_ = socket_ ? open_unix_socket(device) : open_serial(device);
    // A real adapter: close, 500 kbit/s, open. Our own boards skip these lines.
    const char setup[] = "C\rS6\rO\r";
    write_all(setup, sizeof setup - 1);
  }
  ~SlcanTransport() override { ::close(fd_); }
  SlcanTransport(const SlcanTransport&) = delete;
  SlcanTransport& operator=(const SlcanTransport&) = delete;

  bool send(const CanFrame& frame) override {
    char line[can::kSlcanMaxLine];
    const std::size_t n = can::slcan_encode(frame, line, sizeof line);
    if (n == 0) return false;  // not a frame: the link is fine
    send_failed_ = !write_all(line, n);
    return !send_failed_;
  }

  int receive(CanFrame& frame, int timeout_ms) override {
    for (;;) {
      while (next_ < filled_) {
        if (decoder_.push(buffer_[next_++], frame)) return 1;
      }
      if (closed_) return -1;
      pollfd p{fd_, POLLIN, 0};
      const int ready = ::poll(&p, 1, timeout_ms);
      if (ready < 0 && errno == EINTR) continue;
      if (ready == 0) return 0;
      const ssize_t n = ready < 0 ? -1 : ::read(fd_, buffer_, sizeof buffer_);
      if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
      if (n <= 0) {  // end of file, or EIO from a pty whose other side closed
        closed_ = true;
        return -1;
      }
      next_ = 0;
      filled_ = std::size_t(n);
    }
  }

  const std::string& name() const override { return name_; }
  int fd() const override { return fd_; }
  bool has_buffered_input() const override { return next_ < filled_; }
  bool bus_off() const override { return send_failed_; }

 private:
  bool write_all(const char* data, std::size_t length) {
    while (length > 0) {
      // MSG_NOSIGNAL: a peer that went away is an error to report, not a SIGPIPE.
      const ssize_t n = socket_ ? ::send(fd_, data, length, MSG_NOSIGNAL) : ::write(fd_, data, length);
      if (n < 0) {
        if (errno == EINTR) continue;
        if (errno == EAGAIN) {
          pollfd p{fd_, POLLOUT, 0};
          if (::poll(&p, 1, 1000) <= 0) return false;
          continue;
        }
        return false;
      }
      data += n;
      length -= std::size_t(n);
    }
    return true;
  }

  int fd_ = -1;
  bool socket_ = false;
  std::string name_;
  can::SlcanDecoder decoder_;
  char buffer_[512] = {};
  std::size_t next_ = 0, filled_ = 0;
  bool closed_ = false;
  bool send_failed_ = false;
};

}  // namespace

std::unique_ptr<CanTransport> open_slcan(const std::string& device) { return std::make_unique<SlcanTransport>(device); }

}  // namespace dynweigh::hal::linux_can
