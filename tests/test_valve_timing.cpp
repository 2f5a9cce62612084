// Supervision and timing that know the valve the indicator has: valves from 10 to 80 ms
// dead time and 40 to 300 ms stroke, left at the datasheet's parameters (30 ms, 80 ms), with feedback
// that reports `moving` through the stroke and feedback that reports end positions only.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "dynweigh/firmware/valve_timing.hpp"
#include "dynweigh/model/oiml_r61_limits.hpp"
#include "dynweigh/sim/plant_family.hpp"
#include "support/valve_rig.hpp"

namespace dynweigh::testing {
namespace {

using firmware::Fault;

sim::Scene scene_with_valve(double dead_ms, double stroke_ms) {
  sim::Scene scene = sim::default_scene();
  scene.valve.dead_time_s = dead_ms / 1000.0;
  scene.valve.full_stroke_s = stroke_ms / 1000.0;
  return scene;
}

const char* kind_name(ValveFeedbackKind kind) {
  return kind == ValveFeedbackKind::reports_moving ? "moving" : "end-positions";
}

// Each valve doses four times into one container (12 kg of the silo's 18), every strategy, with no
// fault; the fifth dose's close is ignored by a valve stuck open, and the supervisor says so within
// 100 ms of the moment this valve, healthy, would have shut.
TEST(ValveTiming, HealthyValvesRaiseNothingAndAStuckOneIsCaughtWithin100msOfItsShut) {
  double worst_latency_s = -1.0;
  for (ValveFeedbackKind kind : {ValveFeedbackKind::reports_moving, ValveFeedbackKind::end_positions_only}) {
    for (double dead_ms : {10.0, 30.0, 50.0, 80.0}) {
      for (double stroke_ms : {40.0, 80.0, 150.0, 300.0}) {
        SCOPED_TRACE(std::string(kind_name(kind)) + " feedback, dead " + std::to_string(int(dead_ms)) +
                     " ms, stroke " + std::to_string(int(stroke_ms)) + " ms");
        ValveRig rig(scene_with_valve(dead_ms, stroke_ms), kind);
        rig.idle(60);
        for (const char* strategy : {"model", "twostage", "preact", "learn"}) {
          const std::string answer = rig.run_command(std::string("dose 3000 ") + strategy);
          ASSERT_NE(answer.find("RESULT"), std::string::npos) << strategy << ": " << answer;
          rig.idle(100);
          ASSERT_EQ(rig.indicator().fault(), Fault::none) << strategy << ": " << firmware::fault_name(rig.indicator().fault());
        }
        rig.valve().stick_at_next_close();
        const std::string answer = rig.run_command("dose 1000 model");
        EXPECT_EQ(answer, "ERR 4 fault valve_stuck_open\n");
        ASSERT_TRUE(rig.detected());
        const double latency_s = rig.detection_after_healthy_shut_s();
        worst_latency_s = std::fmax(worst_latency_s, latency_s);
        EXPECT_LE(latency_s, 0.100 + 1e-9);  // whole jiffies: ten of them is 100 ms, up to rounding
      }
    }
  }
  std::printf("stuck open caught at most %.0f ms after a healthy valve's shut\n", 1000.0 * worst_latency_s);
}

// The project's plant with a 50 ms / 150 ms valve, the indicator at the datasheet's 30 ms / 80 ms:
// the first fill overdoses (the valve lets through what a slower valve does); from the third on, the
// dead time measured from the first impact and the stroke from the feedback time the close, and the
// fills are as good as a valve that keeps its datasheet (same seeds). At 4 kg (four fills, 16 kg of
// the silo's 18) the close is measured on a grown stream. At 3 kg the stream is still young at the
// close, and the plan's room for its growth already keeps the slow valve's first fill within X(1).
constexpr double kValveTargetG = 4000.0;
std::vector<double> fill_errors_g(double dead_ms, double stroke_ms, std::uint64_t seed, int fills,
                                  double target_g = kValveTargetG) {
  ValveRig rig(scene_with_valve(dead_ms, stroke_ms), ValveFeedbackKind::reports_moving, seed);
  rig.idle(60);
  std::vector<double> errors;
  for (int fill = 1; fill <= fills; ++fill) {
    const double before_kg = rig.plant().truth().static_kg;
    const std::string answer = rig.run_command("dose " + std::to_string(int(target_g)));
    EXPECT_NE(answer.find("RESULT"), std::string::npos) << answer;
    rig.idle(100);
    errors.push_back((rig.plant().truth().static_kg - before_kg) * 1000.0 - target_g);
  }
  return errors;
}

TEST(ValveTiming, ASlowValvesOverdoseIsGoneByTheThirdFill) {
  constexpr int kSeeds = 6, kFills = 4;
  const double x2_g = 2.0 * model::oiml_r61_x1_limits(kValveTargetG).initial_verification_g;
  double slow_mean[kFills] = {}, matched_mean[kFills] = {};
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const std::vector<double> slow = fill_errors_g(50.0, 150.0, std::uint64_t(seed), kFills);
    const std::vector<double> matched = fill_errors_g(30.0, 80.0, std::uint64_t(seed), kFills);
    for (int fill = 0; fill < kFills; ++fill) {
      slow_mean[fill] += slow[fill] / kSeeds;
      matched_mean[fill] += matched[fill] / kSeeds;
      if (fill >= 2) {
        EXPECT_LE(slow[fill], x2_g) << "seed " << seed << ", fill " << fill + 1;
      }
    }
  }
  std::printf("dose %.0f, mean error per fill over %d seeds (g): 50/150 ms valve", kValveTargetG, kSeeds);
  for (double e : slow_mean) std::printf(" %+.0f", e);
  std::printf("; 30/80 ms valve (as the datasheet)");
  for (double e : matched_mean) std::printf(" %+.0f", e);
  std::printf("\n");
  // The datasheet's timing: the slow valve overdoses (by 20 g more than the matched one; 45 g before
  // the plan allowed for the let-through no measured close had shown yet, 71 g while it also counted
  // less of the flow's fluctuation in flight).
  EXPECT_GT(slow_mean[0] - matched_mean[0], 10.0);
  const double later_excess = (slow_mean[2] + slow_mean[3] - matched_mean[2] - matched_mean[3]) / 2.0;
  EXPECT_LT(later_excess, 15.0);
}

// The same slow valve at 3 kg, the first fill from a blank indicator: the stream is measured while the
// slow stroke still opens the valve, so its landing rate climbs above its mean. The plan counts that
// growth and aims short (a top-up finishes the fill); trusting the mean overdosed every seed by 84 to
// 124 g. Now five of the six seeds end within X(1) (-15 to +71 g), and none by 90 g or more.
TEST(ValveTiming, ASlowValvesFirstFillOnAYoungStreamIsWithinX1) {
  const double x1_g = model::oiml_r61_x1_limits(3000.0).initial_verification_g;
  int within = 0;
  for (int seed = 1; seed <= 6; ++seed) {
    const double first_g = fill_errors_g(50.0, 150.0, std::uint64_t(seed), 1, 3000.0).front();
    within += std::fabs(first_g) <= x1_g ? 1 : 0;
    EXPECT_LT(first_g, 90.0) << "seed " << seed;
    EXPECT_GT(first_g, -x1_g) << "seed " << seed;
  }
  EXPECT_GE(within, 5);
}

// A fine feed too short for a slow valve to reach half before the close (a few hundredths of a
// second of full flow): the close starts while the valve still travels from open towards half, and
// arrives sooner than a full stroke would. That is no full stroke to learn the valve's closing time
// from: a full close after it (preact's) is healthy, not stuck open.
TEST(ValveTiming, ACloseOnTheWayToHalfTeachesNoFullStroke) {
  for (ValveFeedbackKind kind : {ValveFeedbackKind::reports_moving, ValveFeedbackKind::end_positions_only}) {
    for (const char* fine_s : {"0.02", "0.06"}) {
      SCOPED_TRACE(std::string(kind_name(kind)) + " feedback, model_fine_s " + fine_s);
      ValveRig rig(scene_with_valve(10.0, 300.0), kind);
      rig.idle(60);
      rig.run_command(std::string("param model_fine_s ") + fine_s);
      for (const char* strategy : {"model", "model", "preact"}) {
        const std::string answer = rig.run_command(std::string("dose 3000 ") + strategy);
        ASSERT_NE(answer.find("RESULT"), std::string::npos) << strategy << ": " << answer;
        rig.idle(100);
        ASSERT_EQ(rig.indicator().fault(), Fault::none) << strategy;
      }
    }
  }
}

// A half command from closed: the feedback stands at closed for the dead time, shows `moving`, then
// `half`. The stroke to half is timed apart from the full ones, and what it times is the motion
// alone: from leaving closed to reporting half. Feedback that never shows `moving` (the valve's
// own jump from closed to half) times no motion, and half to closed is no stroke to half.
TEST(ValveTiming, AStrokeFromClosedToHalfIsTimedApartAndWithoutItsDeadTime) {
  using firmware::ValveCommand;
  using firmware::ValvePosition;
  using D = firmware::ValveTimingMonitor::Direction;
  firmware::ValveTimingMonitor monitor;
  monitor.configure(10.0f);
  const auto jiffies = [&monitor](ValveCommand command, ValvePosition position, int n) {
    for (int i = 0; i < n; ++i) monitor.observe(command, 0.0f, position);
  };
  jiffies(ValveCommand::closed, ValvePosition::closed, 5);
  jiffies(ValveCommand::half, ValvePosition::closed, 4);  // the dead time
  jiffies(ValveCommand::half, ValvePosition::moving, 7);
  jiffies(ValveCommand::half, ValvePosition::half, 5);
  EXPECT_EQ(monitor.strokes(D::to_half), 1u);
  EXPECT_EQ(monitor.strokes(D::opening), 0u);
  EXPECT_FLOAT_EQ(monitor.mean_motion_ms(D::to_half), 70.0f);
  jiffies(ValveCommand::closed, ValvePosition::half, 2);
  jiffies(ValveCommand::closed, ValvePosition::moving, 7);
  jiffies(ValveCommand::closed, ValvePosition::closed, 5);
  EXPECT_EQ(monitor.strokes(D::to_half), 1u);
  EXPECT_EQ(monitor.strokes(D::closing), 0u);
  jiffies(ValveCommand::half, ValvePosition::closed, 4);
  jiffies(ValveCommand::half, ValvePosition::half, 5);
  EXPECT_EQ(monitor.strokes(D::to_half), 2u);
  EXPECT_FLOAT_EQ(monitor.mean_motion_ms(D::to_half), 70.0f) << "a stroke that showed no motion times none";
}

// A new material's first 500 g dose on the family's plants (seed 1) that need all three of its
// pulses, installed as the bench installs them (the valve left at its datasheet's 80 ms stroke,
// where the family's take 40 to 300 ms). A valve module whose feedback shows the gate moving and at
// half has each pulse's stroke to half timed, and the pulses after the first are sized with it; one
// with limit switches alone leaves the law the datasheet's travel (and what each pulse's mass
// teaches of it). Over the plants, more first doses end within X(1) with the timed travel.
TEST(ValveTiming, TheTimedHalfStrokeSizesANewMaterialsPulses) {
  constexpr double kTargetG = 500.0;
  const double limit_g = model::oiml_r61_x1_limits(kTargetG).initial_verification_g;
  int within[2] = {0, 0}, doses = 0;
  for (std::uint32_t index = 0; index < 50; ++index) {
    const sim::FamilyPlant plant = sim::draw_family_plant(1, index);
    const sim::Scene& s = plant.scene;
    if (s.silo.fill_kg < 1.0) continue;
    int kind_index = 0;
    for (ValveFeedbackKind kind : {ValveFeedbackKind::reports_moving, ValveFeedbackKind::end_positions_only}) {
      ValveRig rig(s, kind);
      const std::vector<std::string> installation = {
          "param bore_mm " + std::to_string(s.silo.bore_m * 1000.0),
          "param fall_mm " + std::to_string(s.column.fall_height_m * 1000.0),
          "param container_mm " + std::to_string(s.column.container_diameter_m * 1000.0),
          "param density " + std::to_string(plant.density_guess), "param valve_dead_ms 30",
          "param valve_stroke_ms 80"};
      for (const std::string& line : installation) rig.run_command(line);
      rig.idle(100);
      const double before_kg = rig.plant().truth().static_kg;
      const std::string answer = rig.run_command("dose 500");
      const double error_g = (rig.plant().truth().static_kg - before_kg) * 1000.0 - kTargetG;
      if (kind_index == 0 && answer.find("topups=3") == std::string::npos) break;
      if (kind_index == 0) ++doses;
      if (std::fabs(error_g) <= limit_g) ++within[kind_index];
      ++kind_index;
    }
  }
  std::printf("first 500 g doses with three pulses: %d; within X(1): %d with the half stroke timed, %d with limit "
              "switches alone\n", doses, within[0], within[1]);
  ASSERT_GE(doses, 15);
  EXPECT_GE(within[0], within[1] + 3);
}

}  // namespace
}  // namespace dynweigh::testing
