// A reading between a close and a top-up pulse only sizes the pulse (sizing_reading.hpp): three
// estimates agreeing within 2 g, with a standard error within 3 g, size it where the fill is short by
// more than it accepts plus that error; a result is always certified in full.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "dynweigh/firmware/dose_plan.hpp"
#include "dynweigh/firmware/sizing_reading.hpp"
#include "dynweigh/model/oiml_r61_limits.hpp"
#include "support/console_session.hpp"
#include "support/fault_rig.hpp"

namespace dynweigh::testing {
namespace {

// The jiffies a dose's valve was open (full or half), as [first, past-the-last) spans, from its
// trace; and the trace's length when the dose ended.
struct ValveSpans {
  std::vector<std::pair<std::size_t, std::size_t>> open;
  std::size_t ended = 0;
};

ValveSpans valve_spans(const std::vector<hal::host::TraceRow>& trace, std::size_t from) {
  ValveSpans spans;
  for (std::size_t i = from; i < trace.size(); ++i) {
    const bool open = trace[i].valve != 0;
    const bool was_open = i > from && trace[i - 1].valve != 0;
    if (open && !was_open) spans.open.push_back({i, trace.size()});
    if (!open && was_open) spans.open.back().second = i;
  }
  spans.ended = trace.size();
  return spans;
}

sim::Scene scene_with_silo(double fill_kg) {
  sim::Scene scene = sim::default_scene();
  scene.silo.fill_kg = fill_kg;
  return scene;
}

using firmware::RecentEstimates;
using firmware::SizingReading;

TEST(SizingReading, TheSpreadIsTheNewestEstimatesOfTheRing) {
  // Seven written into a ring of five: the newest three are at 6 % 5, 5 % 5 and 4.
  const float ring[5] = {1001.0f, 1000.0f, 990.0f, 980.0f, 1000.5f};
  EXPECT_FLOAT_EQ(firmware::newest_estimates_spread_g(RecentEstimates{ring, 5, 7}, 3), 1.0f);
  EXPECT_FLOAT_EQ(firmware::newest_estimates_spread_g(RecentEstimates{ring, 5, 7}, 5), 21.0f);
  EXPECT_TRUE(std::isinf(firmware::newest_estimates_spread_g(RecentEstimates{ring, 5, 2}, 3)));
  EXPECT_TRUE(std::isinf(firmware::newest_estimates_spread_g(RecentEstimates{ring, 5, 7}, 6)));
}

TEST(SizingReading, ThreeAgreeingEstimatesSizeAPulseWhereTheFillIsClearlyShort) {
  const float agreeing[5] = {1800.0f, 1801.5f, 1802.0f, 0.0f, 0.0f};
  const RecentEstimates three{agreeing, 5, 3};
  const float accepted_short_g = 6.3f;  // 0.3 of a 21 g warning band
  const float least_g = accepted_short_g + SizingReading::kStandardErrorG;
  EXPECT_TRUE(firmware::reading_sizes_pulse(three, 2.9f, 200.0f, accepted_short_g));
  EXPECT_TRUE(firmware::reading_sizes_pulse(three, 0.5f, least_g + 0.01f, accepted_short_g));
  // Short by no more than it accepts plus the reading's error: certified in full.
  EXPECT_FALSE(firmware::reading_sizes_pulse(three, 0.5f, least_g, accepted_short_g));
  EXPECT_FALSE(firmware::reading_sizes_pulse(three, 0.5f, -20.0f, accepted_short_g));
  // Unsure, or not yet three.
  EXPECT_FALSE(firmware::reading_sizes_pulse(three, 3.1f, 200.0f, accepted_short_g));
  EXPECT_FALSE(firmware::reading_sizes_pulse(three, NAN, 200.0f, accepted_short_g));
  EXPECT_FALSE(firmware::reading_sizes_pulse(RecentEstimates{agreeing, 5, 2}, 0.5f, 200.0f, accepted_short_g));
}

TEST(SizingReading, EstimatesThatDisagreeByMoreThanTwoGramsSizeNothing) {
  const float disagreeing[5] = {1800.0f, 1802.1f, 1801.0f, 0.0f, 0.0f};
  EXPECT_FALSE(firmware::reading_sizes_pulse(RecentEstimates{disagreeing, 5, 3}, 0.5f, 200.0f, 6.3f));
  // The older disagreement has left the newest three.
  const float settled[5] = {1800.0f, 1802.1f, 1801.0f, 1801.5f, 0.0f};
  EXPECT_TRUE(firmware::reading_sizes_pulse(RecentEstimates{settled, 5, 4}, 0.5f, 200.0f, 6.3f));
}

// 2 kg fills on the default scene close blind, aim short and are finished by pulses. The reading
// after the close and after each pulse but the last only sizes the next pulse: the pulse follows
// sooner after its reading's grains landed than the result follows the last pulse's (the same
// landing time, the same platform), and the fills still end within X(1).
TEST(SizingReading, APulseFollowsItsReadingSoonerThanTheResultFollowsTheLastPulse) {
  int pulses_sized = 0;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    ConsoleSession c(sim::default_scene(), seed);
    for (int fill = 0; fill < 3; ++fill) {
      const std::size_t from = c.trace().size();
      const double before_kg = c.session().plant().truth().static_kg;
      const std::string result = c.run({"dose 2000"});
      ASSERT_NE(result.find("RESULT "), std::string::npos) << result;
      const double error_g = (c.session().plant().truth().static_kg - before_kg) * 1000.0 - 2000.0;
      EXPECT_LE(std::fabs(error_g), model::oiml_r61_x1_limits(2000.0).initial_verification_g) << result;
      const ValveSpans s = valve_spans(c.trace(), from);
      ASSERT_GE(s.open.size(), 2u) << "seed " << seed << " fill " << fill << ": no pulse: " << result;
      const std::size_t result_wait = s.ended - s.open.back().second;
      for (std::size_t k = 1; k < s.open.size(); ++k) {
        const std::size_t pulse_wait = s.open[k].first - s.open[k - 1].second;
        EXPECT_LT(pulse_wait, result_wait) << "seed " << seed << " fill " << fill << " pulse " << k;
        ++pulses_sized;
      }
    }
  }
  EXPECT_GE(pulses_sized, 9);
}

// The silo runs dry at the close: the pulse its reading sized moves nothing. That is judged on a
// reading certified in full, and the dose ends in its RESULT (not a fault: the close delivered
// most of the target), the valve shut, the result what the plant holds.
TEST(SizingReading, APulseThatMovedNothingEndsTheDoseOnAReadingCertifiedInFull) {
  ConsoleSession c(scene_with_silo(1.5));
  c.idle(20);
  const double before_kg = c.session().plant().truth().static_kg;
  const std::string out = c.run({"dose 2000"});
  const std::string result = out.substr(0, out.find('\n'));
  ASSERT_EQ(result.rfind("RESULT ", 0), 0u) << out;
  EXPECT_EQ(field(result, "topups"), "2") << result;  // the close, a pulse that ran the silo dry, one that moved nothing
  const double fill_g = (c.session().plant().truth().static_kg - before_kg) * 1000.0;
  EXPECT_NEAR(std::stod(field(result, "final")), fill_g, 1.5) << result;
  c.idle(50);
  EXPECT_EQ(c.session().plant().truth().stroke, 0.0);
}

// The jiffies of a 2 kg model dose on the default scene, from the rig's start: the close and the
// first pulse's opening.
struct DoseJiffies {
  std::uint32_t dose = 0, close = 0, first_pulse = 0;
};

DoseJiffies time_a_two_kilogram_dose() {
  FaultRig dry(hal::host::SensorFaultPlan{}, hal::host::ValveFault::none, 0);
  dry.idle(100);
  DoseJiffies j;
  j.dose = dry.jiffy();
  dry.run_command("dose 2000", 1);
  bool opened = false;
  for (int i = 0; i < 2000 && j.first_pulse == 0; ++i) {
    dry.step();
    const bool open = dry.plant().truth().stroke > 0.0;
    if (open && !opened && j.close != 0) j.first_pulse = dry.jiffy();
    if (!open && opened && j.close == 0) j.close = dry.jiffy();
    opened = open;
  }
  return j;
}

// The load cell's reading freezes at the model's close, far short of the target. The pulse sized on
// it moves nothing the scale sees; that is judged on the reading certified in full, and the dose ends
// after that one pulse with the valve shut, not overdosed.
TEST(SizingReading, AReadingFrozenAtTheCloseEndsTheDoseAfterOnePulse) {
  const DoseJiffies j = time_a_two_kilogram_dose();
  ASSERT_GT(j.first_pulse, j.close) << j.close;
  hal::host::SensorFaultPlan freeze;
  freeze.fault = hal::host::SensorFault::freeze;
  freeze.at_jiffy = j.close;
  FaultRig rig(freeze, hal::host::ValveFault::none, 0);
  rig.idle(100);
  ASSERT_EQ(rig.jiffy(), j.dose);
  const double before_kg = rig.plant().truth().static_kg;
  const std::string answer = rig.run_command("dose 2000", 6000);
  const double fill_g = (rig.plant().truth().static_kg - before_kg) * 1000.0;
  EXPECT_LE(fill_g, 2000.0 + model::oiml_r61_x1_limits(2000.0).in_service_g) << answer;
  const std::string result = answer.substr(0, answer.find('\n'));
  if (result.rfind("RESULT ", 0) == 0) {
    EXPECT_EQ(field(result, "topups"), "1") << answer;
  }
  rig.idle(50);
  EXPECT_EQ(rig.plant().truth().stroke, 0.0) << answer;
}

}  // namespace
}  // namespace dynweigh::testing
