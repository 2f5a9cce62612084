#pragma once
// SLCAN (Lawicel) ASCII framing, as Linux's slcand and many USB-CAN adapters speak it:
//   t<iii><l><dd...>\r        standard data frame (3 hex digits of id, DLC digit, 2 hex per byte)
//   T<iiiiiiii><l><dd...>\r   extended data frame
//   r<iii><l>\r, R<iiiiiiii><l>\r  remote frames
// Adapters also send `\r` (command accepted), `\a` (error), `z\r`/`Z\r` (transmitted) and
// answers to commands (`V1234\r`, `F00\r`); the decoder skips every line that is not a frame,
// counting only malformed frame lines as errors. Freestanding: no heap, no OS.
#include <cstddef>
#include <cstdint>

#include "dynweigh/hal/can/can_frame.hpp"

namespace dynweigh::hal::can {

// The longest frame line: T + 8 id + 1 dlc + 16 data + \r.
inline constexpr std::size_t kSlcanMaxLine = 27;

// Writes the frame's line (with its trailing \r); returns its length, or 0 if `capacity` is too
// small or the frame is invalid (DLC over 8, id out of range).
std::size_t slcan_encode(const CanFrame& frame, char* out, std::size_t capacity);

class SlcanDecoder {
 public:
  // Feeds one byte; true when it completes a well-formed frame, which is then in `frame`.
  bool push(char c, CanFrame& frame);
  std::uint32_t errors() const { return errors_; }

 private:
  bool parse(CanFrame& frame) const;

  char line_[kSlcanMaxLine + 1] = {};
  std::size_t length_ = 0;
  bool overflow_ = false;
  std::uint32_t errors_ = 0;
};

}  // namespace dynweigh::hal::can
