// The kept doses and their curve (dose_history.hpp): a power law recovered from doses on it, the
// doses near the open time asked for weighing most, the exponent held within [1, 4], the cube through
// a single dose and beyond the longer of two, and what does not fit the compact record left out or
// refused.
#include <gtest/gtest.h>

#include <cmath>

#include "dynweigh/firmware/dose_history.hpp"

namespace dynweigh::testing {
namespace {

using firmware::DoseHistory;

// fill = scale t^k, in grams, t in seconds.
void add_on_power_law(DoseHistory& h, double scale, double k, std::initializer_list<double> open_s) {
  for (double t : open_s) h.add(float(t), float(scale * std::pow(t, k)));
}

TEST(DoseHistory, RecoversThePowerLawItsDosesLieOn) {
  DoseHistory h;
  add_on_power_law(h, 1e5, 3.0, {0.08, 0.10, 0.12, 0.15});
  const DoseHistory::PowerLaw law = h.near(0.12f);
  ASSERT_TRUE(law.valid);
  EXPECT_NEAR(law.k, 3.0f, 0.02f);
  EXPECT_NEAR(law.fill_g(0.13f), 1e5 * std::pow(0.13, 3.0), 0.01 * 1e5 * std::pow(0.13, 3.0));
  // Beyond the longest dose too: the curve, not a line, carries the fill on.
  EXPECT_NEAR(law.fill_g(0.2f), 800.0f, 16.0f);
  EXPECT_NEAR(law.growth_g_per_s(0.12f), 3.0 * 1e5 * 0.0144, 0.02 * 3.0 * 1e5 * 0.0144);
}

// Short doses that closed with the gate part open (fill ~ t^3) and long ones on a settled stream
// (fill ~ t): near each, the curve follows its own.
TEST(DoseHistory, TheDosesNearTheOpenTimeAskedForWeighMost) {
  DoseHistory h;
  add_on_power_law(h, 1e5, 3.0, {0.08, 0.10, 0.12});
  add_on_power_law(h, 2000.0, 1.0, {2.0, 3.0, 4.0});
  const DoseHistory::PowerLaw short_law = h.near(0.1f), long_law = h.near(3.0f);
  ASSERT_TRUE(short_law.valid);
  ASSERT_TRUE(long_law.valid);
  EXPECT_NEAR(short_law.k, 3.0f, 0.1f);
  EXPECT_NEAR(long_law.k, 1.0f, 0.1f);
  EXPECT_NEAR(long_law.fill_g(3.5f), 7000.0f, 70.0f);
}

TEST(DoseHistory, TheExponentStaysWithinOneAndFour) {
  DoseHistory falling, steep;
  falling.add(0.1f, 300.0f);
  falling.add(0.2f, 200.0f);  // a silo running low: no valve delivers less for longer
  add_on_power_law(steep, 1e8, 6.0, {0.1, 0.12, 0.14});
  EXPECT_FLOAT_EQ(falling.near(0.15f).k, 1.0f);
  EXPECT_FLOAT_EQ(steep.near(0.12f).k, 4.0f);
}

// No dose tells no curve. One tells its fill, not its slope: beyond it the fill is taken to grow as
// the cube of the open time, as it does while the gate is still opening (twice the open time, eight
// times the fill), not as the line through it. Three doses all at one open time tell their fill, not
// their slope (taken as 2).
TEST(DoseHistory, OneDoseGivesTheCubeThroughItAndASlopeOnlyWhereTheDosesDiffer) {
  DoseHistory h;
  EXPECT_FALSE(h.near(0.1f).valid);
  h.add(0.1f, 100.0f);
  const DoseHistory::PowerLaw one = h.near(0.2f);
  ASSERT_TRUE(one.valid);
  EXPECT_FLOAT_EQ(one.k, 3.0f);
  EXPECT_NEAR(one.fill_g(0.1f), 100.0f, 0.01f);
  EXPECT_NEAR(one.fill_g(0.2f), 800.0f, 0.1f);
  EXPECT_NEAR(one.growth_g_per_s(0.1f), 3000.0f, 0.5f);
  h.add(0.1f, 120.0f);
  h.add(0.1f, 110.0f);
  const DoseHistory::PowerLaw law = h.near(0.2f);
  ASSERT_TRUE(law.valid);
  EXPECT_FLOAT_EQ(law.k, 2.0f);
  EXPECT_NEAR(law.fill_g(0.1f), std::cbrt(100.0 * 120.0 * 110.0), 0.5);
  EXPECT_FALSE(h.near(0.0f).valid);
  EXPECT_FALSE(h.near(-1.0f).valid);
}

// Two doses a fifth apart in open time whose fills hardly differ (a valve's jitter, a flow's
// start-up): their fit's slope holds between them, but beyond the longer the curve grows at least as
// the cube through it. A third dose's slope is taken as it is.
TEST(DoseHistory, BeyondTheLongerOfTwoDosesTheCurveGrowsAtLeastAsTheCube) {
  DoseHistory h;
  h.add(0.14f, 205.0f);
  h.add(0.17f, 213.0f);
  const DoseHistory::PowerLaw within = h.near(0.16f), beyond = h.near(0.3f);
  ASSERT_TRUE(within.valid);
  ASSERT_TRUE(beyond.valid);
  EXPECT_FLOAT_EQ(within.k, 1.0f);
  EXPECT_FLOAT_EQ(beyond.k, 3.0f);
  EXPECT_NEAR(beyond.fill_g(0.17f), 213.0f, 0.05f);
  EXPECT_NEAR(beyond.fill_g(0.34f), 8.0f * 213.0f, 0.5f);
  DoseHistory steep;
  add_on_power_law(steep, 1e6, 3.5, {0.14, 0.17});
  EXPECT_NEAR(steep.near(0.3f).k, 3.5f, 0.01f) << "a steeper fit stands";
  h.add(0.2f, 230.0f);
  EXPECT_LT(h.near(0.3f).k, 1.5f);
}

TEST(DoseHistory, KeepsTheLastEightAndLeavesOutWhatTheRecordCannotHold) {
  DoseHistory h;
  h.add(0.0f, 100.0f);
  h.add(-0.1f, 100.0f);
  h.add(std::nanf(""), 100.0f);
  h.add(0.1f, 2.0f);          // lighter than the scale tells a curve by
  h.add(7.0f, 5000.0f);       // longer than 6.5 s: a measured close
  h.add(1.0f, 70000.0f);      // heavier than 65 kg
  h.add(0.1f, std::nanf(""));
  EXPECT_EQ(h.size(), 0u);
  for (int i = 1; i <= 10; ++i) h.add(0.01f * float(i), 10.0f * float(i));
  EXPECT_EQ(h.size(), DoseHistory::kDoses);
  EXPECT_EQ(h.next(), 2u);
  EXPECT_EQ(h.entry(0).open_100us, 900u);  // the ninth replaced the first
  EXPECT_EQ(h.entry(1).final_g, 100u);     // the tenth the second
  EXPECT_EQ(h.entry(2).open_100us, 300u);
}

TEST(DoseHistory, RestoreRefusesWhatNoDoseCanLeave) {
  DoseHistory::Entry entries[DoseHistory::kDoses] = {{1000, 100}, {1200, 180}, {1500, 330}};
  DoseHistory h;
  EXPECT_TRUE(h.restore(entries, 3, 3));
  EXPECT_EQ(h.size(), 3u);
  EXPECT_TRUE(h.near(0.12f).valid);
  DoseHistory bad;
  EXPECT_FALSE(bad.restore(entries, 9, 0));  // more doses than slots
  EXPECT_FALSE(bad.restore(entries, 3, 8));  // a slot out of range
  EXPECT_FALSE(bad.restore(entries, 3, 1));  // three doses, the next not behind them
  EXPECT_FALSE(bad.restore(entries, 4, 4));  // the fourth is empty
  entries[1].final_g = 2;
  EXPECT_FALSE(bad.restore(entries, 3, 3));  // a dose too light to keep
  EXPECT_EQ(bad.size(), 0u);
  for (auto& e : entries) e = {800, 50};
  EXPECT_TRUE(bad.restore(entries, 8, 5));  // full: the next may be any slot
}

}  // namespace
}  // namespace dynweigh::testing
