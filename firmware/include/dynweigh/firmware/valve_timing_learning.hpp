#pragma once
// What the scale measured of the valve's timing while it dosed a material, kept with that material
// in the settings record so that a restart does not send the next dose back to the datasheet: the
// dead time from the doses' first impacts (a running mean over the last few doses) and the time to
// the end position the valve's feedback showed (a mean over its full strokes).
#include <cstdint>

namespace dynweigh::firmware {

struct ValveTimingLearning {
  float dead_s = 0.0f;             // the running mean of the measured dead times
  float travel_s = 0.0f;           // the feedback's mean time from the command to the end position
  std::uint16_t dead_doses = 0;    // 0: no dead time measured
  std::uint16_t travel_strokes = 0;  // 0: no stroke timed
  bool empty() const { return dead_doses == 0 && travel_strokes == 0; }
};

// What no valve can show: a dead time or a travel that is not finite, negative, or a second or more.
inline bool sane(const ValveTimingLearning& v) {
  constexpr float kLongestS = 1.0f;
  const bool dead_ok = v.dead_doses == 0 || (v.dead_s >= 0.0f && v.dead_s < kLongestS);
  const bool travel_ok = v.travel_strokes == 0 || (v.travel_s > 0.0f && v.travel_s < kLongestS);
  return dead_ok && travel_ok;
}

}  // namespace dynweigh::firmware
