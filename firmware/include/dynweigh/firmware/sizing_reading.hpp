#pragma once
// A reading that only sizes a top-up pulse. Between a close (or a pulse) and the next pulse, the
// certified reading is what the pulse is sized from (or judged by), and the pulse's own scatter is
// grams (the valve's timing jitter times the flow: a 10 to 20 g pulse lands 5 to 10 g either side
// of its aim on the plant family). Certifying that reading to the division, as a result is
// certified, costs the settling fit's estimates the time to agree within half a division. So
// where a pulse follows whatever the reading's last grams say (the fill is short by more than it
// accepts, plus the reading's own uncertainty), kAgreeingEstimates successive estimates agreeing
// within kAgreementG, with a standard error within kStandardErrorG, size it. A result that is
// reported is always certified in full (docs/strategies.md, Dynamic weighing).
#include <cstdint>

namespace dynweigh::firmware {

// The settling fit's last estimates of the final weight, in a ring of `ring_size` of which
// `written` were written (the newest at (written - 1) % ring_size).
struct RecentEstimates {
  const float* ring = nullptr;
  std::uint32_t ring_size = 0;
  std::uint32_t written = 0;
};

// Highest minus lowest of the newest `count` estimates; infinity while fewer were written.
float newest_estimates_spread_g(const RecentEstimates& recent, std::uint32_t count);

struct SizingReading {
  static constexpr std::uint32_t kAgreeingEstimates = 3;
  static constexpr float kAgreementG = 2.0f;
  static constexpr float kStandardErrorG = 3.0f;
};

// Whether the reading, `deficit_g` short of the target (negative: over it), sizes the next pulse
// now: its estimates agree and are sure enough, and the fill is short by more than
// `accepted_short_g` (what it may end short by without a pulse) plus kStandardErrorG.
bool reading_sizes_pulse(const RecentEstimates& recent, float standard_error_g, float deficit_g,
                         float accepted_short_g);

}  // namespace dynweigh::firmware
