#include "dynweigh/modbus/endpoint.hpp"

#include <cstdlib>

namespace dynweigh::modbus {
namespace {

bool whole_number(const std::string& text, long minimum, long maximum, long& value) {
  if (text.empty() || text.size() > 9 || text.find_first_not_of("0123456789") != std::string::npos) return false;
  value = std::strtol(text.c_str(), nullptr, 10);
  return value >= minimum && value <= maximum;
}

}  // namespace

std::optional<Endpoint> parse_endpoint(const std::string& text, std::string& error) {
  Endpoint endpoint;
  endpoint.text = text;
  if (text.rfind("tcp:", 0) == 0) {
    const std::string rest = text.substr(4);
    const std::size_t colon = rest.rfind(':');
    long port = 0;
    if (colon == std::string::npos || colon == 0 || !whole_number(rest.substr(colon + 1), 1, 65535, port)) {
      error = "tcp:<host>:<port> needs a host and a port 1..65535, not '" + text + "'";
      return std::nullopt;
    }
    endpoint.kind = Endpoint::Kind::tcp;
    endpoint.host = rest.substr(0, colon);
    endpoint.port = rest.substr(colon + 1);
    return endpoint;
  }
  if (text.rfind("rtu:", 0) == 0) {
    // The device may hold colons itself: the last three fields are baud, framing and unit id.
    const std::string rest = text.substr(4);
    const std::size_t unit_colon = rest.rfind(':');
    const std::size_t framing_colon = unit_colon == std::string::npos ? unit_colon : rest.rfind(':', unit_colon - 1);
    const std::size_t baud_colon =
        framing_colon == std::string::npos || framing_colon == 0 ? std::string::npos : rest.rfind(':', framing_colon - 1);
    const std::string usage =
        "rtu:<device>:<baud>:<8N1|8E1|8O1>:<unit id 1..247> expected, not '" + text + "'";
    if (baud_colon == std::string::npos || baud_colon == 0) {
      error = usage;
      return std::nullopt;
    }
    long baud = 0, unit = 0;
    const std::string framing = rest.substr(framing_colon + 1, unit_colon - framing_colon - 1);
    if (!whole_number(rest.substr(baud_colon + 1, framing_colon - baud_colon - 1), 300, 4000000, baud) ||
        !whole_number(rest.substr(unit_colon + 1), 1, 247, unit) ||
        (framing != "8N1" && framing != "8E1" && framing != "8O1")) {
      error = usage;
      return std::nullopt;
    }
    endpoint.kind = Endpoint::Kind::rtu;
    endpoint.device = rest.substr(0, baud_colon);
    endpoint.baud = int(baud);
    endpoint.parity = framing[1];
    endpoint.unit_id = int(unit);
    return endpoint;
  }
  error = "must be tcp:<host>:<port> or rtu:<device>:<baud>:<8N1|8E1|8O1>:<unit id>, not '" + text + "'";
  return std::nullopt;
}

}  // namespace dynweigh::modbus
