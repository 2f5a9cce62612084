#include <gtest/gtest.h>

#include <cmath>

#include "dynweigh/model/sliding_line_fit.hpp"

namespace dynweigh::model {
namespace {

TEST(SlidingLineFit, RecoversSlopeAndPresentValueOfARampWithoutLag) {
  SlidingLineFit<float, 64> fit;
  fit.set_window(50);
  for (int i = 0; i < 200; ++i) fit.push(30000.0f + 24.0f * float(i));
  const auto line = fit.fit();
  EXPECT_NEAR(line.slope_per_sample, 24.0f, 1e-3f);
  EXPECT_NEAR(line.value_at_newest, 30000.0f + 24.0f * 199.0f, 0.05f);
}

TEST(SlidingLineFit, AveragesARingingThatSpansWholePeriods) {
  SlidingLineFit<double, 128> fit;
  fit.set_window(100);
  // 12 Hz ringing sampled at 100 Hz; a 1 s window holds twelve periods.
  for (int i = 0; i < 100; ++i) fit.push(10.0 * i + 50.0 * std::sin(2.0 * M_PI * 12.0 * i / 100.0));
  EXPECT_NEAR(fit.fit().slope_per_sample, 10.0, 0.2);
}

TEST(SlidingLineFit, ForgetsSamplesOlderThanTheWindow) {
  SlidingLineFit<float, 32> fit;
  fit.set_window(10);
  for (int i = 0; i < 10; ++i) fit.push(1000.0f);  // flat
  for (int i = 0; i < 10; ++i) fit.push(float(i) * 5.0f);
  EXPECT_NEAR(fit.fit().slope_per_sample, 5.0f, 1e-4f);
  EXPECT_EQ(fit.count(), 10u);
}

TEST(SlidingLineFit, WindowIsClampedToCapacity) {
  SlidingLineFit<float, 16> fit;
  fit.set_window(1000);
  EXPECT_EQ(fit.window(), 16u);
}

}  // namespace
}  // namespace dynweigh::model
