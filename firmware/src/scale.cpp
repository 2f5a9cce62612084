#include "dynweigh/firmware/scale.hpp"

#include <cmath>

namespace dynweigh::firmware {

void Scale::start(const Calibration& calibration) {
  if (!calibration.zero_set) return;
  reference_counts_ = calibration.zero_counts;
  has_reference_ = true;
}

void Scale::configure(const Parameters& p) {
  filter_.configure(p.filter(), p.get(ParameterId::filter_hz), p.get(ParameterId::jiffy_ms) / 1000.0f);
  if (has_sample_) filter_.reset(filtered_counts_);  // otherwise the first sample primes it
}

float Scale::take(std::int32_t raw_counts) {
  if (!has_reference_) {
    reference_counts_ = raw_counts;
    has_reference_ = true;
  }
  raw_sample_ = raw_counts;
  return relative_counts(raw_counts);
}

void Scale::filter(float screened_counts) {
  screened_counts_ = screened_counts;
  has_sample_ = true;
  filtered_counts_ = filter_.push(screened_counts_);
}

float Scale::net_g(float counts, const Calibration& calibration) const {
  if (!calibration.valid()) return 0.0f;
  return (counts - zero_relative_counts(calibration)) / calibration.counts_per_gram - tare_g_;
}

float Scale::mean_above_zero(const Calibration& calibration) const {
  return standstill_.mean_above(calibration.zero_counts) - calibration.zero_fraction;
}

void Scale::start_adjustment(Adjustment kind, std::int32_t grams) {
  adjustment_ = kind;
  adjustment_grams_ = grams;
  adjustment_jiffies_ = 0;
  standstill_.start();
}

Scale::AdjustmentEnd Scale::advance_adjustment(bool fresh_sample, Calibration& calibration,
                                                const Parameters& p) {
  if (adjustment_ == Adjustment::none) return AdjustmentEnd::running;
  if (fresh_sample) standstill_.push(raw_sample_);
  ++adjustment_jiffies_;
  const float floor_counts =
      adjustment_ == Adjustment::span ? kSpanSteadiness * std::fabs(mean_above_zero(calibration)) : 0.0f;
  if (standstill_.steady(floor_counts)) {
    const Adjustment kind = adjustment_;
    adjustment_ = Adjustment::none;
    return kind == Adjustment::zero ? finish_zero(calibration, p) : finish_span(calibration);
  }
  const float timeout_jiffies = p.get(ParameterId::standstill_timeout_s) * 1000.0f / p.get(ParameterId::jiffy_ms);
  if (float(adjustment_jiffies_) >= timeout_jiffies) {
    adjustment_ = Adjustment::none;
    return AdjustmentEnd::in_motion;
  }
  return AdjustmentEnd::running;
}

Scale::AdjustmentEnd Scale::finish_zero(Calibration& cal, const Parameters& p) {
  bool zero_setting = false;
  if (cal.valid()) {
    const float gross_g = mean_above_zero(cal) / cal.counts_per_gram;
    zero_setting = std::fabs(gross_g) <= kZeroSettingRangeOfCapacity * p.get(ParameterId::capacity_g);
  }
  const StandstillAverage::Reading zero = standstill_.mean();
  cal.zero_counts = zero.whole;
  cal.zero_fraction = zero.fraction;
  cal.zero_set = true;
  if (!zero_setting) cal.span_set = false;
  tare_g_ = 0.0f;
  rebase_to_zero(cal);
  return zero_setting ? AdjustmentEnd::zero_set : AdjustmentEnd::zero_adjusted;
}

Scale::AdjustmentEnd Scale::finish_span(Calibration& cal) {
  const float span_counts = mean_above_zero(cal);
  if (span_counts < kMinimumSpanCounts) return AdjustmentEnd::span_too_small;
  cal.counts_per_gram = span_counts / float(adjustment_grams_);
  cal.span_set = true;
  tare_g_ = 0.0f;
  return span_counts < kCoarseSpanCounts ? AdjustmentEnd::span_coarse : AdjustmentEnd::span_set;
}

// The float counts the filter and the dose use start at the new zero: small numbers near it keep
// their precision at any offset.
void Scale::rebase_to_zero(const Calibration& calibration) {
  reference_counts_ = calibration.zero_counts;
  has_reference_ = true;
  screened_counts_ = relative_counts(raw_sample_);
  filtered_counts_ = zero_relative_counts(calibration);  // the scale stands at its zero
  filter_.reset(filtered_counts_);
}

}  // namespace dynweigh::firmware
