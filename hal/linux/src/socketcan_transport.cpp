// The socketcan transport (docs/can-protocol.md): a raw CAN socket bound to one interface (can0, vcan0).
#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "dynweigh/hal/linux/can_transport.hpp"

namespace dynweigh::hal::linux_can {
namespace {

class SocketCanTransport final : public CanTransport {
 public:
  explicit SocketCanTransport(const std::string& interface_name) : name_("socketcan:" + interface_name) {
    fd_ = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
    if (fd_ < 0) {
      throw std::runtime_error("socketcan: no CAN sockets on this kernel (" + std::string(std::strerror(errno)) +
                               "); use udp: or slcan:");
    }
    if (interface_name.size() >= IFNAMSIZ) {
      ::close(fd_);
      throw std::invalid_argument("socketcan: interface name too long: " + interface_name);
    }
    ifreq request{};
    std::strncpy(request.ifr_name, interface_name.c_str(), IFNAMSIZ - 1);
    if (::ioctl(fd_, SIOCGIFINDEX, &request) != 0) {
      ::close(fd_);
      throw std::runtime_error("socketcan: no interface " + interface_name);
    }
    sockaddr_can address{};
    address.can_family = AF_CAN;
    address.can_ifindex = request.ifr_ifindex;
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
      const std::string reason = std::strerror(errno);
      ::close(fd_);
      throw std::runtime_error("socketcan: cannot bind " + interface_name + ": " + reason);
    }
    // The controller's bus-off and its restart come as error frames once asked for.
    const can_err_mask_t errors = CAN_ERR_BUSOFF | CAN_ERR_RESTARTED;
    ::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &errors, sizeof errors);
  }
  ~SocketCanTransport() override { ::close(fd_); }
  SocketCanTransport(const SocketCanTransport&) = delete;
  SocketCanTransport& operator=(const SocketCanTransport&) = delete;

  bool send(const CanFrame& frame) override {
    can_frame out{};
    out.can_id = frame.id | (frame.extended ? CAN_EFF_FLAG : 0u) | (frame.remote ? CAN_RTR_FLAG : 0u);
    out.len = frame.dlc > 8 ? 8 : frame.dlc;
    std::memcpy(out.data, frame.data, out.len);
    send_failed_ = true;  // until the frame is queued: a full queue for 1 s is a dead bus too
    for (int attempt = 0; attempt < 1000; ++attempt) {
      const ssize_t n = ::write(fd_, &out, sizeof out);
      if (n == ssize_t(sizeof out)) {
        send_failed_ = false;
        return true;
      }
      if (n < 0 && (errno == EINTR)) continue;
      if (n < 0 && (errno == ENOBUFS || errno == EAGAIN)) {  // transmit queue full: wait a little
        pollfd p{fd_, POLLOUT, 0};
        ::poll(&p, 1, 1);
        continue;
      }
      return false;
    }
    return false;
  }

  int receive(CanFrame& frame, int timeout_ms) override {
    for (;;) {
      pollfd p{fd_, POLLIN, 0};
      const int ready = ::poll(&p, 1, timeout_ms);
      if (ready < 0 && errno == EINTR) continue;
      if (ready <= 0) return 0;
      can_frame in{};
      const ssize_t n = ::read(fd_, &in, sizeof in);
      if (n < 0) {
        if (errno == EINTR || errno == EAGAIN) continue;
        return -1;
      }
      if (n == ssize_t(sizeof in) && (in.can_id & CAN_ERR_FLAG)) {
        if (in.can_id & CAN_ERR_BUSOFF) controller_bus_off_ = true;
        if (in.can_id & CAN_ERR_RESTARTED) controller_bus_off_ = false;
        return 0;  // no frame, but news: the caller looks at bus_off()
      }
      if (n != ssize_t(sizeof in) || in.len > 8) continue;
      CanFrame f;
      f.extended = (in.can_id & CAN_EFF_FLAG) != 0;
      f.remote = (in.can_id & CAN_RTR_FLAG) != 0;
      f.id = in.can_id & (f.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
      f.dlc = in.len;
      std::memcpy(f.data, in.data, in.len);
      frame = f;
      return 1;
    }
  }

  const std::string& name() const override { return name_; }
  int fd() const override { return fd_; }
  bool bus_off() const override { return controller_bus_off_ || send_failed_; }

 private:
  int fd_ = -1;
  bool controller_bus_off_ = false;
  bool send_failed_ = false;
  std::string name_;
};

}  // namespace

std::unique_ptr<CanTransport> open_socketcan(const std::string& interface_name) {
  return std::make_unique<SocketCanTransport>(interface_name);
}

}  // namespace dynweigh::hal::linux_can
