#pragma once
// One classic CAN frame (11-bit or 29-bit identifier, 0..8 data bytes), independent of any OS.
#include <cstdint>

namespace dynweigh::hal::can {

struct CanFrame {
  std::uint32_t id = 0;      // 11-bit (standard) or 29-bit (extended) identifier
  bool extended = false;
  bool remote = false;       // remote transmission request: no data
  std::uint8_t dlc = 0;      // 0..8
  std::uint8_t data[8] = {};
};

inline bool operator==(const CanFrame& a, const CanFrame& b) {
  if (a.id != b.id || a.extended != b.extended || a.remote != b.remote || a.dlc != b.dlc) return false;
  for (int i = 0; i < a.dlc && i < 8; ++i) {
    if (a.data[i] != b.data[i]) return false;
  }
  return true;
}

// The 16-byte Linux `struct can_frame` (docs/can-protocol.md, udp transport): can_id u32 little-endian with the
// EFF (bit 31) and RTR (bit 30) flags, len u8, 3 pad bytes, data[8].
inline constexpr unsigned kLinuxFrameSize = 16;
inline constexpr std::uint32_t kLinuxEffFlag = 0x80000000u;
inline constexpr std::uint32_t kLinuxRtrFlag = 0x40000000u;
inline constexpr std::uint32_t kLinuxErrFlag = 0x20000000u;

void to_linux_bytes(const CanFrame& frame, std::uint8_t (&out)[kLinuxFrameSize]);
// False for error frames, a length over 8 or an identifier out of range.
bool from_linux_bytes(const std::uint8_t* bytes, unsigned length, CanFrame& frame);

}  // namespace dynweigh::hal::can
