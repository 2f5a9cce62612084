#include <cerrno>
#include <cstdlib>
#include <stdexcept>

#include "dynweigh/hal/linux/can_transport.hpp"

namespace dynweigh::hal::linux_can {
namespace {

std::uint16_t parse_port(const std::string& text, const std::string& whole) {
  if (text.empty() || text.size() > 5 || text.find_first_not_of("0123456789") != std::string::npos) {
    throw std::invalid_argument("bad port '" + text + "' in udp:" + whole);
  }
  const unsigned long value = std::strtoul(text.c_str(), nullptr, 10);
  if (value == 0 || value > 65535) throw std::invalid_argument("port out of range in udp:" + whole);
  return std::uint16_t(value);
}

}  // namespace

UdpSpec parse_udp_spec(const std::string& text) {
  const auto at = text.find('@');
  const auto colon = text.rfind(':');
  if (at == std::string::npos || colon == std::string::npos || colon < at) {
    throw std::invalid_argument("udp transport must be udp:<bind_port>@<peer_host>:<peer_port>, not udp:" + text);
  }
  UdpSpec spec;
  spec.bind_port = parse_port(text.substr(0, at), text);
  spec.peer_host = text.substr(at + 1, colon - at - 1);
  spec.peer_port = parse_port(text.substr(colon + 1), text);
  if (spec.peer_host.empty()) throw std::invalid_argument("missing peer host in udp:" + text);
  return spec;
}

std::unique_ptr<CanTransport> open_can_transport(const std::string& spec) {
  const auto colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  const std::string rest = colon == std::string::npos ? "" : spec.substr(colon + 1);
  if (kind == "udp") return open_udp(parse_udp_spec(rest));
  if (kind == "socketcan") {
    if (rest.empty()) throw std::invalid_argument("socketcan transport needs an interface: socketcan:<ifname>");
    return open_socketcan(rest);
  }
  if (kind == "slcan") {
    if (rest.empty()) throw std::invalid_argument("slcan transport needs a device: slcan:<device>");
    return open_slcan(rest);
  }
  throw std::invalid_argument("unknown CAN transport '" + spec +
                              "' (socketcan:<ifname>, udp:<port>@<host>:<port> or slcan:<device>)");
}

}  // namespace dynweigh::hal::linux_can
