// `zero` and `cal` (OIML R76): both wait for standstill and take the reading averaged over a stable
// window (StandstillAverage), or answer `ERR 3 in motion` after `standstill_timeout_s`.
// - `zero` on a calibrated scale with the load within 4 % of Max of its zero is zero-setting.
// - `zero` anywhere else, or on a scale without a span, is adjustment: the zero goes wherever the
//   load cell stands (the whole ADC range), and the span is invalid until `cal <grams>`.
// - `cal <grams>` with a test weight on the zeroed scale adjusts the span.
#include <cmath>

#include "dynweigh/firmware/indicator.hpp"

namespace dynweigh::firmware {
namespace {
constexpr float kZeroSettingRangeOfCapacity = 0.04f;  // OIML R76: more is a load, not a zero error
// The span's mean must stand within this fraction of the span: a quarter of the 0.02 % a span is
// adjusted to (the load cell's noise may ask for more, never less).
constexpr float kSpanSteadiness = 5e-5f;

float mean_above_zero(const StandstillAverage& standstill, const Calibration& cal) {
  return standstill.mean_above(cal.zero_counts) - cal.zero_fraction;
}
}  // namespace

void Indicator::start_adjustment(Adjustment::Kind kind, std::int32_t grams) {
  adjustment_ = Adjustment{kind, grams, 0};
  standstill_.start();
}

void Indicator::advance_adjustment(bool fresh_sample) {
  if (adjustment_.kind == Adjustment::Kind::none) return;
  if (fresh_sample) standstill_.push(raw_sample_);
  ++adjustment_.jiffies;
  const float floor_counts = adjustment_.kind == Adjustment::Kind::span
                                 ? kSpanSteadiness * std::fabs(mean_above_zero(standstill_, settings_.calibration))
                                 : 0.0f;
  if (standstill_.steady(floor_counts)) {
    const Adjustment::Kind kind = adjustment_.kind;
    adjustment_.kind = Adjustment::Kind::none;
    return kind == Adjustment::Kind::zero ? finish_zero() : finish_span();
  }
  const Parameters& p = settings_.parameters;
  const float timeout_jiffies = p.get(ParameterId::standstill_timeout_s) * 1000.0f / p.get(ParameterId::jiffy_ms);
  if (float(adjustment_.jiffies) >= timeout_jiffies) {
    adjustment_.kind = Adjustment::Kind::none;
    error(3, "in motion");
  }
}

void Indicator::finish_zero() {
  Calibration& cal = settings_.calibration;
  bool zero_setting = false;
  if (cal.valid()) {
    const float gross_g = mean_above_zero(standstill_, cal) / cal.counts_per_gram;
    zero_setting = std::fabs(gross_g) <= kZeroSettingRangeOfCapacity * settings_.parameters.get(ParameterId::capacity_g);
  }
  const StandstillAverage::Reading zero = standstill_.mean();
  cal.zero_counts = zero.whole;
  cal.zero_fraction = zero.fraction;
  cal.zero_set = true;
  if (!zero_setting) cal.span_set = false;
  tare_g_ = 0.0f;
  settings_changed_ = true;
  rebase_to_zero();
  if (!zero_setting) console_.line("NOTE adjustment: new zero; no span until cal <grams> with a test weight");
  ok();
}

void Indicator::finish_span() {
  Calibration& cal = settings_.calibration;
  const float span_counts = mean_above_zero(standstill_, cal);
  if (span_counts < kMinimumSpanCounts) return error(2, "load too small to calibrate");
  cal.counts_per_gram = span_counts / float(adjustment_.grams);
  cal.span_set = true;
  tare_g_ = 0.0f;
  settings_changed_ = true;
  if (span_counts < kCoarseSpanCounts) {
    console_.write("NOTE coarse span: ");
    console_.write_decimal(1.0f / cal.counts_per_gram, 1);
    console_.line(" g per count; a heavier test weight or more gain resolves the scale better");
  }
  ok();
}

// The float counts the filter and the dose use start at the new zero: small numbers near it keep
// their precision at any offset.
void Indicator::rebase_to_zero() {
  reference_counts_ = settings_.calibration.zero_counts;
  has_reference_ = true;
  raw_counts_ = relative_counts(raw_sample_);
  screened_counts_ = raw_counts_;
  filtered_counts_ = zero_relative_counts();  // the scale stands at its zero
  filter_.reset(filtered_counts_);
  supervisor_.reset();  // its outlier screen held counts relative to the old reference
}

}  // namespace dynweigh::firmware
