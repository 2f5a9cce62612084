#pragma once
// The tunables of the console's `param` (docs/console.md) and the firmware's own, each declared once with its range, default
// and description: the `param` command, persistence and the defaults all read this one table.
#include <cstddef>
#include <cstdint>

namespace dynweigh::firmware {

enum class ParameterId : std::uint8_t {
  bore_mm,
  fall_mm,
  container_mm,
  density,
  capacity_g,
  jiffy_ms,
  filter,
  filter_hz,
  preact_g,
  valve_dead_ms,
  valve_stroke_ms,
  repose_deg,
  stable_band_g,
  stable_ms,
  dose_timeout_s,
  model_window_ms,
  impact_settle_ms,
  subjiffy,
  certify,
  twostage_band_g,
  twostage_preact_g,
  model_fine_s,
  pile_rise,
  model_estimator,
  platform_hz,
  platform_kg,
  standstill_timeout_s,
  echo,
  twostage_coarse_g,
  plc_watchdog_ms,
  oiml_class,  // `class`
  tol_warn_low_g,
  tol_warn_high_g,
  tol_reject_low_g,
  tol_reject_high_g,
  tol_action,
  topup_max,
  topup_ms,
  auto_discharge,
  empty_band_g,
  discharge_timeout_s,
  count
};

inline constexpr std::size_t kParameterCount = static_cast<std::size_t>(ParameterId::count);

struct ParameterSpec {
  const char* name;
  const char* description;
  float minimum;
  float maximum;
  float default_value;
  const char* const* choices;  // a named setting (the value is the index), or nullptr
  std::uint8_t choice_count;
  bool read_only = false;  // the board decides it: `param` shows it, nothing sets it
};

const ParameterSpec& parameter_spec(ParameterId id);

// The `param` listing (one `name=value  # description` line a parameter, then OK) fits in this
// many bytes: parameters.cpp checks it at compile time, the console reserves it before answering.
inline constexpr std::size_t kParameterListingMaxBytes = 3500;
// The parameter named `name`, or ParameterId::count.
ParameterId find_parameter(const char* name);

// How a dose's result is certified: `auto` is dynamic for model and learn, stable for the baselines.
enum class CertifyMode : std::uint8_t { automatic = 0, stable = 1, dynamic = 2 };

// Display filters selectable by `param filter <name>`.
enum class FilterKind : std::uint8_t { none = 0, average = 1, iir = 2 };

class Parameters {
 public:
  Parameters();  // every value at its default
  float get(ParameterId id) const { return values_[static_cast<std::size_t>(id)]; }
  // False when out of range or read-only (the value is then unchanged).
  bool set(ParameterId id, float value);

  FilterKind filter() const { return static_cast<FilterKind>(static_cast<int>(get(ParameterId::filter))); }
  CertifyMode certify() const { return static_cast<CertifyMode>(static_cast<int>(get(ParameterId::certify))); }
  const float* raw() const { return values_; }
  float* raw() { return values_; }

 private:
  float values_[kParameterCount];
};

}  // namespace dynweigh::firmware
