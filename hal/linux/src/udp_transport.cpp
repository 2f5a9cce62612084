// The udp transport (docs/can-protocol.md): each datagram is one 16-byte Linux struct can_frame. Binds 127.0.0.1.
#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "dynweigh/hal/linux/can_transport.hpp"

namespace dynweigh::hal::linux_can {
namespace {

class UdpTransport final : public CanTransport {
 public:
  explicit UdpTransport(const UdpSpec& spec) : name_("udp:" + std::to_string(spec.bind_port) + "@" + spec.peer_host + ":" + std::to_string(spec.peer_port)) {
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0) throw std::runtime_error("udp: cannot create a socket: " + std::string(std::strerror(errno)));
    sockaddr_in local{};
    local.sin_family = AF_INET;
    local.sin_port = htons(spec.bind_port);
    local.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0) {
      const std::string reason = std::strerror(errno);
      ::close(fd_);
      throw std::runtime_error("udp: cannot bind 127.0.0.1:" + std::to_string(spec.bind_port) + ": " + reason);
    }
    addrinfo hints{};
    hints.ai_family = AF_INET;
    hints.ai_socktype = SOCK_DGRAM;
    addrinfo* found = nullptr;
    if (::getaddrinfo(spec.peer_host.c_str(), nullptr, &hints, &found) != 0 || !found) {
      ::close(fd_);
      throw std::runtime_error("udp: cannot resolve peer host '" + spec.peer_host + "'");
    }
    std::memcpy(&peer_, found->ai_addr, sizeof peer_);
    ::freeaddrinfo(found);
    peer_.sin_port = htons(spec.peer_port);
  }
  ~UdpTransport() override { ::close(fd_); }
  UdpTransport(const UdpTransport&) = delete;
  UdpTransport& operator=(const UdpTransport&) = delete;

  bool send(const CanFrame& frame) override {
    std::uint8_t bytes[can::kLinuxFrameSize];
    can::to_linux_bytes(frame, bytes);
    for (;;) {
      const ssize_t n = ::sendto(fd_, bytes, sizeof bytes, 0, reinterpret_cast<const sockaddr*>(&peer_), sizeof peer_);
      if (n < 0 && errno == EINTR) continue;
      // ECONNREFUSED: an ICMP from an earlier datagram to a peer not yet listening; not fatal.
      send_failed_ = !(n == ssize_t(sizeof bytes) || (n < 0 && errno == ECONNREFUSED));
      return !send_failed_;
    }
  }

  int receive(CanFrame& frame, int timeout_ms) override {
    for (;;) {
      pollfd p{fd_, POLLIN, 0};
      const int ready = ::poll(&p, 1, timeout_ms);
      if (ready < 0 && errno == EINTR) continue;
      if (ready <= 0) return 0;
      std::uint8_t bytes[64];
      const ssize_t n = ::recv(fd_, bytes, sizeof bytes, 0);
      if (n < 0) {
        if (errno == EINTR || errno == ECONNREFUSED || errno == EAGAIN) continue;
        return -1;
      }
      if (can::from_linux_bytes(bytes, unsigned(n), frame)) return 1;
      // A datagram that is not a frame: ignore it, as a CAN controller ignores a bad frame.
    }
  }

  const std::string& name() const override { return name_; }
  int fd() const override { return fd_; }
  bool bus_off() const override { return send_failed_; }

 private:
  int fd_ = -1;
  bool send_failed_ = false;
  sockaddr_in peer_{};
  std::string name_;
};

}  // namespace

std::unique_ptr<CanTransport> open_udp(const UdpSpec& spec) { return std::make_unique<UdpTransport>(spec); }

}  // namespace dynweigh::hal::linux_can
