#include "dynweigh/modbus/result_fields.hpp"

#include <cstdlib>
#include <cstring>

namespace dynweigh::modbus {
namespace {

// The value after ` key=` in `line`, or nullptr.
const char* value_of(const char* line, const char* key) {
  const std::size_t key_length = std::strlen(key);
  for (const char* p = line; (p = std::strstr(p, key)) != nullptr; p += key_length) {
    if ((p == line || p[-1] == ' ') && p[key_length] == '=') return p + key_length + 1;
  }
  return nullptr;
}

long number_of(const char* line, const char* key) {
  const char* value = value_of(line, key);
  return value ? std::strtol(value, nullptr, 10) : 0;
}

std::uint16_t tolerance_of(const char* line) {
  const char* value = value_of(line, "tolerance");
  if (!value) return 0;
  static constexpr const char* kNames[] = {"ok", "warn_low", "warn_high", "low", "high"};
  for (std::uint16_t i = 0; i < 5; ++i) {
    const std::size_t n = std::strlen(kNames[i]);
    if (std::strncmp(value, kNames[i], n) == 0 && (value[n] == ' ' || value[n] == '\0')) return i;
  }
  return std::uint16_t(std::strtol(value, nullptr, 10));
}

}  // namespace

bool parse_result_line(const char* line, ResultFields& fields) {
  if (std::strncmp(line, "RESULT ", 7) != 0) return false;
  fields.final_g = std::int32_t(number_of(line, "final"));
  fields.error_g = std::int32_t(number_of(line, "error"));
  fields.time_ms = std::uint32_t(number_of(line, "time"));
  fields.tolerance = tolerance_of(line);
  fields.topups = std::uint16_t(number_of(line, "topups"));
  return true;
}

}  // namespace dynweigh::modbus
