#include "dynweigh/firmware/sizing_reading.hpp"

#include <cmath>

namespace dynweigh::firmware {

float newest_estimates_spread_g(const RecentEstimates& recent, std::uint32_t count) {
  if (count == 0 || count > recent.ring_size || recent.written < count) return INFINITY;
  float low = INFINITY, high = -INFINITY;
  for (std::uint32_t i = 1; i <= count; ++i) {
    const float e = recent.ring[(recent.written - i) % recent.ring_size];
    low = e < low ? e : low;
    high = e > high ? e : high;
  }
  return high - low;
}

bool reading_sizes_pulse(const RecentEstimates& recent, float standard_error_g, float deficit_g,
                         float accepted_short_g) {
  if (!(standard_error_g <= SizingReading::kStandardErrorG)) return false;
  if (!(deficit_g > accepted_short_g + SizingReading::kStandardErrorG)) return false;
  return newest_estimates_spread_g(recent, SizingReading::kAgreeingEstimates) <= SizingReading::kAgreementG;
}

}  // namespace dynweigh::firmware
