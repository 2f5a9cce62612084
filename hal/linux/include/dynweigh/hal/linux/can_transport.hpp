#pragma once
// A CAN link as the Linux target sees it (docs/can-protocol.md, "Transports"): frames in, frames out, one file
// descriptor to wait on. Three implementations carry exactly the same frames:
//   socketcan:<ifname>                       raw CAN socket (PF_CAN, SOCK_RAW)
//   udp:<bind_port>@<peer_host>:<peer_port>  16-byte struct can_frame datagrams on 127.0.0.1
//   slcan:<device>                           Lawicel ASCII on a tty, pty or a unix-domain socket
//                                            (QEMU's `-chardev socket,path=...,server=on`)
#include <cstdint>
#include <memory>
#include <string>

#include "dynweigh/hal/can/can_frame.hpp"

namespace dynweigh::hal::linux_can {

using can::CanFrame;

class CanTransport {
 public:
  virtual ~CanTransport() = default;
  // False if the frame could not be handed to the link (peer gone, buffer full for 1 s).
  virtual bool send(const CanFrame& frame) = 0;
  // 1: a frame is in `frame`; 0: nothing within `timeout_ms` (-1 waits for ever); -1: the link
  // is closed (end of file on a serial line or socket).
  virtual int receive(CanFrame& frame, int timeout_ms) = 0;
  virtual const std::string& name() const = 0;
  // For poll(2) beside other descriptors; frames may also wait in a buffer (has_buffered_input).
  virtual int fd() const = 0;
  virtual bool has_buffered_input() const { return false; }
  // True while no frame can get onto the link: the CAN controller reported bus-off (socketcan), or
  // the last send failed (interface down, peer gone). The board reports it to the indicator as the
  // load cell's link status (firmware::LinkStatus::bus_off); the firmware never sees the transport.
  virtual bool bus_off() const = 0;
};

struct UdpSpec {
  std::uint16_t bind_port = 0;
  std::string peer_host;
  std::uint16_t peer_port = 0;
};

// Parses `udp:` specs without the prefix ("5001@127.0.0.1:5000"); throws std::invalid_argument.
UdpSpec parse_udp_spec(const std::string& text);

std::unique_ptr<CanTransport> open_udp(const UdpSpec& spec);
std::unique_ptr<CanTransport> open_socketcan(const std::string& interface_name);
std::unique_ptr<CanTransport> open_slcan(const std::string& device);

// "socketcan:vcan0", "udp:5001@127.0.0.1:5000" or "slcan:/dev/pts/3"; throws std::runtime_error
// (std::invalid_argument for a malformed spec) with a one-line reason.
std::unique_ptr<CanTransport> open_can_transport(const std::string& spec);

}  // namespace dynweigh::hal::linux_can
