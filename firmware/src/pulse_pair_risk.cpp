#include "dynweigh/firmware/pulse_pair_risk.hpp"

#include <cmath>

namespace dynweigh::firmware {
namespace {
constexpr float kInvSqrt2Pi = 0.39894228f;
// Below this a spread is none: the scale reads a pulse to about a gram, never better than this.
constexpr float kLeastSpreadG = 0.1f;
// A tail this unlikely adds nothing a choice among aims could see.
constexpr float kNegligibleChance = 1e-6f;

float density(float z) { return kInvSqrt2Pi * std::exp(-0.5f * z * z); }

// The standard normal's chance of exceeding z, given its density there: Zelen and Severo's
// polynomial (Abramowitz and Stegun 26.2.17, off by less than 1e-7), one exponential in all where
// erfc would take several: the Cortex-M's jiffy has room for a few dozen.
float upper_tail(float z, float density_at_z) {
  const float t = 1.0f / (1.0f + 0.2316419f * std::fabs(z));
  const float tail =
      density_at_z * t * (0.31938153f + t * (-0.356563782f + t * (1.781477937f + t * (-1.821255978f + t * 1.330274429f))));
  return z >= 0.0f ? tail : 1.0f - tail;
}
float upper_tail(float z) { return upper_tail(z, density(z)); }
float held_spread(float spread_g) { return spread_g > kLeastSpreadG ? spread_g : kLeastSpreadG; }

// The chance that a last pulse that must bring `mass_g` ends the fill beyond the limit either way.
float last_miss_chance(float mass_g, const LastPulseSpread& last, float limit_g) {
  return 2.0f * upper_tail(limit_g / held_spread(last.at_zero_g + last.per_g * mass_g));
}
}  // namespace

float pulse_ends_short_chance(float left_g, float spread_g, float short_g) {
  return upper_tail((short_g - left_g) / held_spread(spread_g));
}

float pulse_ends_over_chance(float left_g, float spread_g, float over_g) {
  return upper_tail((left_g + over_g) / held_spread(spread_g));
}

float pulse_pair_miss_chance(float deficit_g, float aim_g, float spread_g, const LastPulseSpread& last,
                             float limit_g) {
  const float s = held_spread(spread_g);
  const float left_g = deficit_g - aim_g;  // what the last pulse must bring, on average
  const float overfill = upper_tail((left_g + limit_g) / s);
  const float beyond = (limit_g - left_g) / s;
  const float density_beyond = density(beyond);
  const float needs_last = upper_tail(beyond, density_beyond);
  if (needs_last < kNegligibleChance) return overfill;
  // What the last pulse must bring when it must bring more than the limit: a normal's tail, taken
  // at its mean less and plus its standard deviation.
  const float ratio = density_beyond / needs_last;
  const float tail_mean_g = left_g + s * ratio;
  const float tail_spread_g = s * std::sqrt(std::fmax(1.0f + beyond * ratio - ratio * ratio, 0.0f));
  const float low_g = std::fmax(tail_mean_g - tail_spread_g, limit_g), high_g = tail_mean_g + tail_spread_g;
  return overfill + needs_last * (last_miss_chance(low_g, last, limit_g) + last_miss_chance(high_g, last, limit_g)) / 2.0f;
}

}  // namespace dynweigh::firmware
