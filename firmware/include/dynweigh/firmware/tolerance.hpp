#pragma once
// A fill's tolerance: two bands below and above the target, the warning band (TL1/TH1) inside the
// reject band (TL2/TH2). By default they come from OIML R61 for the class asked for (`param class`,
// X(x)): the warning band is the class's maximum permissible deviation at initial verification, the
// reject band the one in service. `param tol_*` set a band edge in grams instead (0: from the class).
#include <cstdint>

#include "dynweigh/firmware/parameters.hpp"

namespace dynweigh::firmware {

// The verdict of a result against the bands it was dosed to.
enum class ToleranceVerdict : std::uint8_t { ok = 0, warn_low = 1, warn_high = 2, low = 3, high = 4 };
const char* tolerance_verdict_name(ToleranceVerdict verdict);

// What the indicator does with a result outside the reject band (`param tol_action`).
enum class ToleranceAction : std::uint8_t { accept = 0, topup = 1, hold = 2 };

// Distances from the target, grams, all >= 0.
struct ToleranceBands {
  float warn_low_g = 0.0f;    // TL1
  float warn_high_g = 0.0f;   // TH1
  float reject_low_g = 0.0f;  // TL2
  float reject_high_g = 0.0f; // TH2
};

ToleranceBands tolerance_bands(float target_g, const Parameters& parameters);

// A deviation on a band's edge is inside it; the reject band is judged first, so a warning band set
// wider than the reject band never hides a reject.
ToleranceVerdict judge_tolerance(float error_g, const ToleranceBands& bands);

inline bool outside_reject_band(ToleranceVerdict verdict) {
  return verdict == ToleranceVerdict::low || verdict == ToleranceVerdict::high;
}

}  // namespace dynweigh::firmware
