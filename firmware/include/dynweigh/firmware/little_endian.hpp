#pragma once
// The byte order of everything the indicator keeps in non-volatile memory: little-endian, so a
// record written by one board reads the same on another.
#include <cstdint>

namespace dynweigh::firmware {

inline void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = std::uint8_t(v >> (8 * i));
}

inline std::uint32_t get_u32(const std::uint8_t* p) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= std::uint32_t(p[i]) << (8 * i);
  return v;
}

}  // namespace dynweigh::firmware
