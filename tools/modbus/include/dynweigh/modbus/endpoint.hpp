#pragma once
// A --modbus endpoint: tcp:<host>:<port> or rtu:<device>:<baud>:<8N1|8E1|8O1>:<unit id>.
#include <optional>
#include <string>

namespace dynweigh::modbus {

struct Endpoint {
  enum class Kind { tcp, rtu } kind = Kind::tcp;
  std::string host;  // tcp
  std::string port;  // tcp, as given (a number or a service name)
  std::string device;  // rtu
  int baud = 0;
  char parity = 'N';  // 'N', 'E' or 'O'
  int unit_id = 1;
  std::string text;  // as given, for messages
};

// The endpoint, or nothing with `error` saying why.
std::optional<Endpoint> parse_endpoint(const std::string& text, std::string& error);

}  // namespace dynweigh::modbus
