#pragma once
// The scale: the load cell's counts made grams. It keeps the counts of the last sample (as it came,
// as the outlier screen passed it, and through the display filter), the tare, and the zero and span
// adjustment that waits for standstill (`zero`, `cal`). Grams are computed from counts here and
// nowhere else, by the calibration the indicator's settings keep (passed in: the settings are the
// indicator's, saved by the board).
//
// The counts are kept relative to a reference (the calibrated zero's whole counts, or the first
// sample): small floats near the zero keep their precision at any offset in the ADC's int32 range.
#include <cstdint>

#include "dynweigh/firmware/display_filter.hpp"
#include "dynweigh/firmware/parameters.hpp"
#include "dynweigh/firmware/persistent_settings.hpp"
#include "dynweigh/firmware/standstill_average.hpp"

namespace dynweigh::firmware {

class Scale {
 public:
  // A load cell of 1 count per kg under a 10 kg test weight still has a span (10 counts); fewer than
  // a handful of counts is no load at all. Under kCoarseSpanCounts the answer warns of the resolution.
  static constexpr float kMinimumSpanCounts = 5.0f;
  static constexpr float kCoarseSpanCounts = 100.0f;
  static constexpr float kZeroSettingRangeOfCapacity = 0.04f;  // OIML R76: more is a load, not a zero error
  // The span's mean must stand within this fraction of the span: a quarter of the 0.02 % a span is
  // adjusted to (the load cell's noise may ask for more, never less).
  static constexpr float kSpanSteadiness = 5e-5f;

  // Counts start at the calibrated zero if there is one, else at the first sample.
  void start(const Calibration& calibration);
  void configure(const Parameters& parameters);

  // A fresh sample: its counts relative to the reference, for the outlier screen.
  float take(std::int32_t raw_counts);
  // The counts the screen let through (the sample, or the last good one held), filtered.
  void filter(float screened_counts);
  // `clearfault`: the filter primes again from the next sample.
  void restart_filter() { filter_.restart(); }

  // The one conversion: counts relative to the reference, in grams net of the tare (0 uncalibrated).
  float net_g(float counts, const Calibration& calibration) const;
  float filtered_net_g(const Calibration& calibration) const { return net_g(filtered_counts_, calibration); }
  // The screened sample unfiltered: what a dose's cutoff reads.
  float screened_net_g(const Calibration& calibration) const { return net_g(screened_counts_, calibration); }
  // The load on the platform, tare included, as the capacity limits read it (the net plus the tare).
  float filtered_gross_g(const Calibration& calibration) const {
    return filtered_net_g(calibration) + tare_g_;
  }
  float relative_counts(std::int32_t raw) const { return float(std::int64_t(raw) - reference_counts_); }

  // `tare`: the filtered weight becomes the tare.
  void tare(const Calibration& calibration) { tare_g_ += filtered_net_g(calibration); }
  bool has_sample() const { return has_sample_; }
  std::int32_t raw_sample() const { return raw_sample_; }  // the last fresh sample as it came

  // `zero` and `cal <grams>` (OIML R76): both wait for standstill and take the reading averaged over
  // a stable window, or end `in_motion` after `standstill_timeout_s`.
  // - `zero` on a calibrated scale with the load within 4 % of Max of its zero is zero-setting.
  // - `zero` anywhere else, or on a scale without a span, is adjustment: the zero goes wherever the
  //   load cell stands (the whole ADC range), and the span is invalid until `cal <grams>`.
  // - `cal <grams>` with a test weight on the zeroed scale adjusts the span.
  enum class Adjustment : std::uint8_t { none, zero, span };
  enum class AdjustmentEnd : std::uint8_t {
    running,        // still waiting for standstill (or nothing to adjust)
    zero_set,       // zero-setting: the span stands
    zero_adjusted,  // a new zero; no span until `cal`
    span_set,
    span_coarse,    // set, but under kCoarseSpanCounts
    span_too_small, // under kMinimumSpanCounts: nothing changed
    in_motion,      // no standstill before the timeout: nothing changed
  };
  void start_adjustment(Adjustment kind, std::int32_t grams);
  void cancel_adjustment() { adjustment_ = Adjustment::none; }
  bool adjusting() const { return adjustment_ != Adjustment::none; }
  // Each jiffy: `calibration` changes when the adjustment ends set or adjusted.
  AdjustmentEnd advance_adjustment(bool fresh_sample, Calibration& calibration, const Parameters& parameters);

 private:
  float zero_relative_counts(const Calibration& calibration) const {
    return relative_counts(calibration.zero_counts) + calibration.zero_fraction;
  }
  float mean_above_zero(const Calibration& calibration) const;
  AdjustmentEnd finish_zero(Calibration& calibration, const Parameters& parameters);
  AdjustmentEnd finish_span(Calibration& calibration);
  void rebase_to_zero(const Calibration& calibration);

  DisplayFilter filter_;
  std::int32_t reference_counts_ = 0;  // the calibrated zero's whole counts, or the first sample
  bool has_reference_ = false;
  std::int32_t raw_sample_ = 0;
  float screened_counts_ = 0.0f;  // the sample the filter and the dose use (outliers held out)
  float filtered_counts_ = 0.0f;
  bool has_sample_ = false;
  float tare_g_ = 0.0f;

  Adjustment adjustment_ = Adjustment::none;
  std::int32_t adjustment_grams_ = 0;
  std::uint32_t adjustment_jiffies_ = 0;
  StandstillAverage standstill_;
};

}  // namespace dynweigh::firmware
