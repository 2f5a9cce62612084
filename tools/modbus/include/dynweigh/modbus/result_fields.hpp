#pragma once
// The fields of a console RESULT line a PLC reads, by key (more keys may come; missing ones read 0).
#include <cstdint>

namespace dynweigh::modbus {

struct ResultFields {
  std::int32_t final_g = 0;
  std::int32_t error_g = 0;
  std::uint32_t time_ms = 0;
  std::uint16_t tolerance = 0;  // 0 ok, 1 warn_low, 2 warn_high, 3 low, 4 high
  std::uint16_t topups = 0;
};

// False when `line` is no RESULT line.
bool parse_result_line(const char* line, ResultFields& fields);

}  // namespace dynweigh::modbus
