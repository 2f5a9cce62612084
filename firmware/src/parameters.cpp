#include "dynweigh/firmware/parameters.hpp"

#include <cmath>
#include <cstring>

namespace dynweigh::firmware {
namespace {

constexpr const char* kFilterNames[] = {"none", "avg", "iir"};
constexpr const char* kCertifyNames[] = {"auto", "stable", "dynamic"};
constexpr const char* kEstimatorNames[] = {"line", "observer"};
constexpr const char* kToleranceActionNames[] = {"accept", "topup", "hold"};

// The defaults are the thesis' setup (its table 2.2) and the default scene's valve (docs/scenes.md). `preact_g` is
// tuned for that setup: the mean rest-drop seen through the display filter over 20 fills (docs/console.md, parameters).
constexpr ParameterSpec kSpecs[kParameterCount] = {
    {"bore_mm", "valve bore diameter, mm", 5, 500, 60, nullptr, 0},
    {"fall_mm", "orifice to the empty container's bottom, mm", 10, 10000, 1200, nullptr, 0},
    {"container_mm", "container diameter, mm", 50, 5000, 300, nullptr, 0},
    {"density", "bulk density first guess, kg/m^3", 100, 5000, 1550, nullptr, 0},
    {"capacity_g", "scale maximum, g", 100, 10000000, 50000, nullptr, 0},
    {"jiffy_ms", "control period, ms (read-only: the board's jiffy)", 10, 10, 10, nullptr, 0, true},
    {"filter", "display filter: none, avg (moving average), iir (2nd-order low-pass)", 0, 2, 2,
     kFilterNames, 3},
    {"filter_hz", "display filter corner frequency, Hz", 0.1f, 20, 2, nullptr, 0},
    {"preact_g", "preact strategy: close this far before the target, g", 0, 100000, 393, nullptr, 0},
    {"valve_dead_ms", "valve dead time from command to motion, ms", 0, 1000, 30, nullptr, 0},
    {"valve_stroke_ms", "valve full stroke time, ms", 0, 5000, 80, nullptr, 0},
    {"repose_deg", "angle of repose of the material, degrees", 5, 60, 32, nullptr, 0},
    {"stable_band_g", "stable when the filtered weight stays within this band, g", 0.1f, 1000, 1,
     nullptr, 0},
    {"stable_ms", "... for this long, ms", 50, 10000, 500, nullptr, 0},
    {"dose_timeout_s", "fault when a dose has not reached its target by then, s", 1, 3600, 120,
     nullptr, 0},
    {"model_window_ms", "model strategy: the mean flow over this window (line: its regression window), ms", 100, 1270, 1000, nullptr, 0},
    {"impact_settle_ms", "model strategy, line estimator: ignore this long after the first impact, ms", 0, 5000, 300,
     nullptr, 0},
    {"subjiffy", "time the close within the jiffy (valve delay byte): 1 on, 0 off", 0, 1, 1, nullptr, 0},
    {"certify", "result certification: auto (dynamic for model/learn), stable, dynamic", 0, 2, 0,
     kCertifyNames, 3},
    {"twostage_band_g", "twostage strategy: what the settled fine (half-open) stream adds before its cutoff, g",
     0, 100000, 1000, nullptr, 0},
    {"twostage_preact_g", "twostage strategy: fine cutoff this far before the target (negative: after it), "
     "adapted after each fill, g", -100000, 100000, 140, nullptr, 0},
    {"model_fine_s", "model strategy: half-open fine feed for this many seconds of full flow before the "
     "target (0: the plan's choice)", 0, 10, 0, nullptr, 0},
    {"pile_rise", "model strategy: the heap rises in the container (1), or the fall height stays fixed (0: a "
     "level-held hopper, the ideal model)", 0, 1, 1, nullptr, 0},
    {"model_estimator", "model strategy: observer (Kalman, sees through the ringing) or line (fit, model_window_ms)",
     0, 1, 1, kEstimatorNames, 2},
    {"platform_hz", "platform's natural frequency with platform_kg on it, Hz (tap test); 0: rigid", 0, 40, 12,
     nullptr, 0},
    {"platform_kg", "moving mass at platform_hz (platform and container when the scale reads 0), kg", 0.1f,
     10000, 4, nullptr, 0},
    {"standstill_timeout_s", "zero and cal wait this long for standstill, then ERR 3 in motion, s", 5, 600, 10,
     nullptr, 0},
    {"echo", "echo what is typed on the console: 1 on, 0 off (scripts)", 0, 1, 0, nullptr, 0},
    {"twostage_coarse_g", "twostage strategy: the reading's rise from the switch to the settled fine feed, "
     "adapted after each fill, g", 0, 100000, 1500, nullptr, 0},
    {"plc_watchdog_ms", "abort a PLC's dose after this long without a Modbus request, ms; 0: off", 0, 600000,
     0, nullptr, 0},
    {"class", "OIML R61 class X(x) the tolerance bands come from: x", 0.1f, 100, 1, nullptr, 0},
    {"tol_warn_low_g", "warning band below the target (TL1), g; 0: X(x) at initial verification", 0, 100000, 0,
     nullptr, 0},
    {"tol_warn_high_g", "warning band above the target (TH1), g; 0: X(x) at initial verification", 0, 100000, 0,
     nullptr, 0},
    {"tol_reject_low_g", "reject band below the target (TL2), g; 0: X(x) in service", 0, 100000, 0, nullptr, 0},
    {"tol_reject_high_g", "reject band above the target (TH2), g; 0: X(x) in service", 0, 100000, 0, nullptr, 0},
    {"tol_action", "a result outside the reject band: accept, topup (while low), hold (for accept or topup)", 0,
     2, 0, kToleranceActionNames, 3},
    {"topup_max", "top-up pulses at most per dose", 0, 20, 3, nullptr, 0},
    {"topup_ms", "a top-up pulse of a baseline strategy, ms", 10, 5000, 50, nullptr, 0},
    {"auto_discharge", "1: discharge after each dose", 0, 1, 0, nullptr, 0},
    {"empty_band_g", "empty: gross this near zero, g", 0.1f, 100000, 20, nullptr, 0},
    {"discharge_timeout_s", "fault: not empty by then, s", 1, 3600, 30, nullptr, 0},
};

// The longest text write_decimal(value, 3) gives for a value in [minimum, maximum].
constexpr std::size_t longest_value_text(const ParameterSpec& spec) {
  if (spec.choices) {
    std::size_t longest = 0;
    for (std::uint8_t c = 0; c < spec.choice_count; ++c) {
      std::size_t n = 0;
      while (spec.choices[c][n]) ++n;
      longest = n > longest ? n : longest;
    }
    return longest;
  }
  const float magnitude = -spec.minimum > spec.maximum ? -spec.minimum : spec.maximum;
  std::size_t digits = 1;
  for (float limit = 10.0f; limit <= magnitude; limit *= 10.0f) ++digits;
  return 1 + digits + 4;  // sign, whole digits, point and three decimals
}

constexpr std::size_t text_length(const char* text) {
  std::size_t n = 0;
  while (text[n]) ++n;
  return n;
}

constexpr std::size_t parameter_listing_bytes() {
  std::size_t bytes = 3;  // OK\n
  for (const ParameterSpec& spec : kSpecs) {
    bytes += text_length(spec.name) + 1 + longest_value_text(spec) + 4 + text_length(spec.description) + 1;
  }
  return bytes;
}
static_assert(parameter_listing_bytes() <= kParameterListingMaxBytes,
              "the param listing outgrew kParameterListingMaxBytes: raise it (and the console ring if need be)");

}  // namespace

const ParameterSpec& parameter_spec(ParameterId id) { return kSpecs[static_cast<std::size_t>(id)]; }

ParameterId find_parameter(const char* name) {
  for (std::size_t i = 0; i < kParameterCount; ++i) {
    if (std::strcmp(kSpecs[i].name, name) == 0) return static_cast<ParameterId>(i);
  }
  return ParameterId::count;
}

Parameters::Parameters() {
  for (std::size_t i = 0; i < kParameterCount; ++i) values_[i] = kSpecs[i].default_value;
}

bool Parameters::set(ParameterId id, float value) {
  const ParameterSpec& spec = parameter_spec(id);
  if (spec.read_only) return false;
  if (!(value >= spec.minimum && value <= spec.maximum)) return false;  // also rejects NaN
  if (spec.choices && value != std::floor(value)) return false;
  values_[static_cast<std::size_t>(id)] = value;
  return true;
}

}  // namespace dynweigh::firmware
