#pragma once
// `dynweigh bench --plants random:N --ceiling`: how often any controller of the indicator's kind could
// land a fill within X(1) on a plant, knowing the plant exactly (docs/plant-family.md, *The ceiling*).
// The controller opens the valve once and closes it, then gives at most `pulses` pulses, each the
// valve held half or full open for a time of its choosing, each certified exactly before the next.
// What each action delivers is the plant's own: sampled from the simulator, from rest, over many
// seeds (the valve's dead-time jitter, the flow's start-up and fluctuation). The first close may be
// blind (the valve held open for a time) or ideal: the stream measured perfectly and only the
// close's dead-time jitter left, at full or half open. A dynamic programme over the certified
// deficit finds the policy; the chances are those of that policy's fills, drawn again. Host code.
#include <cstdint>
#include <vector>

#include "dynweigh/sim/scene.hpp"

namespace dynweigh::tools {

// What each action of the controller delivers, as samples in grams.
struct CeilingActions {
  std::vector<std::vector<double>> pulses;  // a pulse: half or full open held for a time
  std::vector<std::vector<double>> blind;   // the first opening held for a time
  double ideal_full_sigma_g = 0.0;          // an ideal close's scatter at full open
  double ideal_half_sigma_g = 0.0;          // ... and at half open
};

// Samples the plant's actions for a fill of `target_g`: `samples` seeds each.
CeilingActions sample_ceiling_actions(const sim::Scene& scene, double target_g, int samples);

struct FillCeiling {
  double first = 0.0;   // chance one fill ends within `limit_g` of the target
  double steady = 0.0;  // chance `steady_fills` fills meet the steady class (every one within `limit_g`
                        // of their mean, the mean within `bias_limit_g` of the target)
};

struct CeilingLimits {
  double limit_g = 0.0;       // X(1)'s initial-verification limit
  double bias_limit_g = 0.0;  // a quarter of its in-service limit
};

// The best policy's chances for a fill of `target_g` with at most `pulses` pulses after the first close.
// For the steady class the policy aims within a share of the limit; the best share is taken.
FillCeiling fill_ceiling(const CeilingActions& actions, double target_g, const CeilingLimits& limits, int pulses,
                         std::uint32_t steady_fills);

}  // namespace dynweigh::tools
