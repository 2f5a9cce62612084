// The console's `estimates`: what a model dose measured of the valve and the material, against the
// plant's truth. The dead time must reveal a valve slower than its datasheet, which the firmware was
// told nothing about.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "support/console_session.hpp"

namespace dynweigh::testing {
namespace {

struct Measured {
  double dead_ms = 0, flow_kg_s = 0, impulse_g = 0, impact_m_s = 0;
  bool impulse_known = false;
};

Measured dose_and_estimate(sim::Scene scene, std::uint64_t seed, const std::string& dose) {
  ConsoleSession c(scene, seed);
  c.idle(20);
  EXPECT_EQ(lines_of(c.run({dose})).size(), 2u) << dose;
  const auto lines = lines_of(c.run({"estimates"}));
  EXPECT_EQ(lines.size(), 6u);  // ESTIMATES, what the material learned (LEARNED, VALVE, PULSES), PLAN, OK
  EXPECT_EQ(lines.back(), "OK");
  Measured m;
  m.dead_ms = std::stod(field(lines.front(), "dead_ms"));
  m.flow_kg_s = std::stod(field(lines.front(), "flow_kg_s"));
  m.impulse_known = field(lines.front(), "impulse_g") != "none";
  if (m.impulse_known) {
    m.impulse_g = std::stod(field(lines.front(), "impulse_g"));
    m.impact_m_s = std::stod(field(lines.front(), "impact_m_s"));
  }
  return m;
}

TEST(DoseEstimates, BeforeAnyModelDoseThereIsNothingToTell) {
  ConsoleSession c;
  EXPECT_EQ(c.run({"estimates"}), "ERR 2 no model dose measured yet\n");
  EXPECT_EQ(c.run({"estimates now"}), "ERR 2 usage: estimates\n");
}

// A baseline's dose teaches the model nothing, but its valve's feedback showed the dead time the
// material keeps (the supervision's leave limit after a restart): `estimates` tells that much.
TEST(DoseEstimates, AfterABaselinesDoseTheValvesSlowestDeadTimeIsTold) {
  ConsoleSession c;
  c.idle(100);
  ASSERT_NE(c.run({"dose 3000 preact"}).find("RESULT"), std::string::npos);
  const auto lines = lines_of(c.run({"estimates"}));
  ASSERT_EQ(lines.size(), 4u);  // LEARNED, VALVE, PULSES, OK
  EXPECT_EQ(lines[0].rfind("LEARNED material=0 law_flow_kg_s=none ", 0), 0u) << lines[0];
  ASSERT_EQ(lines[1].rfind("VALVE material=0 ", 0), 0u) << lines[1];
  // The default scene's valve: 30 ms with 2 ms of jitter, read on the jiffy's grid.
  const double slowest_dead_ms = std::stod(field(lines[1], "slowest_dead_ms"));
  EXPECT_GE(slowest_dead_ms, 25.0) << lines[1];
  EXPECT_LE(slowest_dead_ms, 45.0) << lines[1];
  EXPECT_EQ(lines.back(), "OK");
}

// the default scene's valve (docs/scenes.md): 30 ms dead time with 2 ms jitter. Over seeds the measured dead time centres on
// it (~2 ms early: the first grains leave with some speed), the flow on the plant's, the impact
// speed on sqrt(v0^2 + 2 g h) (4.9 m/s for 1.2 m) - ~7 % high: the flow's start-up (alpha rising
// over 0.15 s) leaves ~70 g less landed than rate x time, which reads as impulse.
TEST(DoseEstimates, DeadTimeFlowAndImpulseOfTheDefaultScene) {
  double dead_sum = 0, worst_dead = 0, worst_flow = 0, speed_sum = 0;
  int speeds = 0;
  constexpr int kSeeds = 8;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const Measured m = dose_and_estimate(sim::default_scene(), seed, "dose 8000");
    dead_sum += m.dead_ms;
    worst_dead = std::fmax(worst_dead, std::fabs(m.dead_ms - 30.0));
    // The plant's mean flow: Beverloo's 2.41 kg/s for the default silo (docs/physics.md).
    worst_flow = std::fmax(worst_flow, std::fabs(m.flow_kg_s / 2.41 - 1.0));
    if (m.impulse_known) {
      speed_sum += m.impact_m_s;
      ++speeds;
    }
  }
  const double mean_speed = speed_sum / speeds;
  std::printf("default scene, %d doses: dead time mean %.1f ms (worst |error| %.1f ms), flow worst %.1f %%, "
              "impact speed mean %.2f m/s over %d\n",
              kSeeds, dead_sum / kSeeds, worst_dead, 100.0 * worst_flow, mean_speed, speeds);
  EXPECT_NEAR(dead_sum / kSeeds, 30.0, 2.0);
  EXPECT_LT(worst_dead, 6.0);
  EXPECT_LT(worst_flow, 0.06);
  EXPECT_GE(speeds, kSeeds / 2);
  EXPECT_NEAR(mean_speed, 4.9, 0.5);
}

// The installer typed the datasheet's 30 ms; the valve takes 55 ms (much slower, and the fault
// supervisor, which allows 40 ms of start margin on the datasheet, calls it stuck). The dose still
// works, and `estimates` shows the valve as it is.
TEST(DoseEstimates, RevealsAValveSlowerThanConfigured) {
  sim::Scene slow = sim::default_scene();
  slow.valve.dead_time_s = 0.055;
  double dead_sum = 0;
  constexpr int kSeeds = 4;
  for (int seed = 1; seed <= kSeeds; ++seed) dead_sum += dose_and_estimate(slow, seed, "dose 6000").dead_ms;
  std::printf("valve with 55 ms dead time, configured 30 ms: measured %.1f ms\n", dead_sum / kSeeds);
  EXPECT_NEAR(dead_sum / kSeeds, 55.0, 3.0);
}

// A slow valve over a series of doses, against the same doses with a valve that keeps its datasheet:
// from the third dose on the model times its close with the dead time it measured, and the overdose
// the datasheet's 30 ms caused is gone.
struct Series {
  double first = 0, later = 0;
  std::string estimates;
};

Series five_doses(double dead_time_s, std::uint64_t seed) {
  sim::Scene scene = sim::default_scene();
  scene.valve.dead_time_s = dead_time_s;
  scene.silo.fill_kg = 40.0;  // five doses of 6 kg
  ConsoleSession c(scene, seed);
  // A class the plain close meets: the plan stays full and nothing is topped up, so the errors are
  // the close's timing alone.
  c.run({"param class 10"});
  c.idle(20);
  Series series;
  for (int dose = 1; dose <= 5; ++dose) {
    const double before = c.session().plant().truth().static_kg;
    const auto lines = lines_of(c.run({"dose 6000"}));
    EXPECT_EQ(lines.size(), 2u) << "dose " << dose << ": " << lines.front() << " " << lines_of(c.run({"status"})).front();
    const double error = (c.session().plant().truth().static_kg - before) * 1000.0 - 6000.0;
    if (dose == 1) series.first = error;
    if (dose >= 3) series.later += error / 3;
  }
  series.estimates = lines_of(c.run({"estimates"})).front();
  return series;
}

TEST(DoseEstimates, AValveSlowerThanConfiguredIsLearnedWithinTwoDoses) {
  constexpr int kSeeds = 4;
  double first_excess = 0, later_excess = 0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const Series slow = five_doses(0.055, std::uint64_t(seed));
    const Series healthy = five_doses(0.030, std::uint64_t(seed));
    first_excess += (slow.first - healthy.first) / kSeeds;
    later_excess += (slow.later - healthy.later) / kSeeds;
    EXPECT_NEAR(std::stod(field(slow.estimates, "dead_used_ms")), 55.0, 4.0) << slow.estimates;
    EXPECT_EQ(field(healthy.estimates, "dead_used_ms"), "30") << healthy.estimates;
  }
  std::printf("valve 55 ms, datasheet 30 ms, dose 6000, against a 30 ms valve: dose 1 %+.1f g, doses 3-5 "
              "%+.1f g\n", first_excess, later_excess);
  // The close comes 25 ms late: ~60 g of let-through too many. The second dose already knows the
  // let-through the first showed (material_learning.hpp); from the third the dead time is learned too.
  EXPECT_GT(first_excess, 30.0);
  EXPECT_LT(std::fabs(later_excess), 15.0);
}

// Within the jitter and the estimate's error the datasheet stands: the bench's scenes dose as before.
TEST(DoseEstimates, TheDatasheetDeadTimeStandsWhenTheValveKeepsIt) {
  ConsoleSession c;
  c.idle(20);
  for (int dose = 1; dose <= 3; ++dose) ASSERT_EQ(lines_of(c.run({"dose 3000"})).size(), 2u);
  const auto estimates = lines_of(c.run({"estimates"})).front();
  EXPECT_EQ(field(estimates, "dead_used_ms"), "30") << estimates;
}

}  // namespace
}  // namespace dynweigh::testing
