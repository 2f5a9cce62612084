// The scale on its own: counts made grams by the calibration, relative to a reference that keeps
// the floats small at any ADC offset; the tare; the gross the capacity limits read.
#include <gtest/gtest.h>

#include "dynweigh/firmware/parameters.hpp"
#include "dynweigh/firmware/scale.hpp"

namespace dynweigh::firmware {
namespace {

// A load cell whose empty platform reads far from 0 (half-way into the int32 range), 2.5 counts a
// gram, the zero's average half a count above its whole counts.
Calibration calibrated() {
  Calibration cal;
  cal.zero_counts = 1000000000;
  cal.zero_fraction = 0.5f;
  cal.counts_per_gram = 2.5f;
  cal.zero_set = true;
  cal.span_set = true;
  return cal;
}

Scale scale_for(const Calibration& cal) {
  Parameters p;
  p.set(ParameterId::filter, float(FilterKind::none));  // the filtered reading is the sample
  Scale scale;
  scale.start(cal);
  scale.configure(p);
  return scale;
}

void take(Scale& scale, std::int32_t raw) { scale.filter(scale.take(raw)); }

TEST(Scale, GramsAreTheCountsAboveTheCalibratedZeroOverTheSpan) {
  const Calibration cal = calibrated();
  Scale scale = scale_for(cal);
  for (const std::int32_t above : {0, 1, 2501, 125000, -40}) {
    const std::int32_t raw = cal.zero_counts + above;
    take(scale, raw);
    EXPECT_FLOAT_EQ(scale.filtered_net_g(cal), cal.counts_above_zero(raw) / cal.counts_per_gram) << above;
    EXPECT_FLOAT_EQ(scale.screened_net_g(cal), scale.filtered_net_g(cal)) << above;
  }
}

TEST(Scale, AnUncalibratedScaleShowsNoGrams) {
  Calibration cal = calibrated();
  cal.span_set = false;
  Scale scale = scale_for(cal);
  take(scale, cal.zero_counts + 5000);
  EXPECT_TRUE(scale.has_sample());
  EXPECT_EQ(scale.filtered_net_g(cal), 0.0f);
  EXPECT_EQ(scale.net_g(1234.0f, cal), 0.0f);
}

TEST(Scale, TareTakesThePresentWeightAndTheGrossKeepsIt) {
  const Calibration cal = calibrated();
  Scale scale = scale_for(cal);
  const std::int32_t raw = cal.zero_counts + 25000;
  take(scale, raw);
  const float load_g = cal.counts_above_zero(raw) / cal.counts_per_gram;
  scale.tare(cal);
  EXPECT_FLOAT_EQ(scale.filtered_net_g(cal), 0.0f);
  EXPECT_FLOAT_EQ(scale.filtered_gross_g(cal), load_g);
  take(scale, raw + 250);  // 100 g more
  EXPECT_FLOAT_EQ(scale.filtered_net_g(cal), 250.0f / cal.counts_per_gram);
  EXPECT_FLOAT_EQ(scale.filtered_gross_g(cal), load_g + 250.0f / cal.counts_per_gram);
}

TEST(Scale, WithoutAZeroTheCountsStartAtTheFirstSample) {
  Calibration cal;  // nothing set
  Scale scale = scale_for(cal);
  const std::int32_t first = -2000000000;
  EXPECT_EQ(scale.take(first), 0.0f);
  EXPECT_EQ(scale.take(first + 7), 7.0f);
  EXPECT_EQ(scale.raw_sample(), first + 7);
}

TEST(Scale, ZeroAdjustmentOnAnUncalibratedScaleSetsTheZeroWhereTheLoadCellStands) {
  Calibration cal;  // nothing set
  Parameters p;
  Scale scale = scale_for(cal);
  const std::int32_t empty = 123456789;
  scale.start_adjustment(Scale::Adjustment::zero, 0);
  Scale::AdjustmentEnd end = Scale::AdjustmentEnd::running;
  for (int jiffy = 0; jiffy < 2000 && end == Scale::AdjustmentEnd::running; ++jiffy) {
    take(scale, empty);
    end = scale.advance_adjustment(true, cal, p);
  }
  EXPECT_EQ(end, Scale::AdjustmentEnd::zero_adjusted);
  EXPECT_FALSE(scale.adjusting());
  EXPECT_TRUE(cal.zero_set);
  EXPECT_FALSE(cal.span_set);
  EXPECT_EQ(cal.zero_counts, empty);
  EXPECT_EQ(cal.zero_fraction, 0.0f);
}

}  // namespace
}  // namespace dynweigh::firmware
