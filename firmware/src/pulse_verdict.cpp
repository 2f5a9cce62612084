#include "dynweigh/firmware/pulse_verdict.hpp"

namespace dynweigh::firmware {
namespace {
constexpr float kNothingSeenShare = 0.03f;
constexpr float kNothingSeenG = 1.0f;
}  // namespace

PulseVerdict judge_pulse(float expected_g, float delivered_g, float pulse_s, float travel_s, bool sized) {
  const float least = kNothingSeenShare * expected_g;
  const bool nothing_seen = delivered_g < (least > kNothingSeenG ? least : kNothingSeenG);
  if (!nothing_seen) return PulseVerdict::delivered;
  return sized && pulse_s < travel_s ? PulseVerdict::parted_too_little : PulseVerdict::moved_nothing;
}

}  // namespace dynweigh::firmware
