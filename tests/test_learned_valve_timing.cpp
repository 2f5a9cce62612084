// The valve's timing as the model strategy uses it: the datasheet's until the scale has measured
// something clearly different, then the measured dead time (from the doses' first impacts) and the
// measured stroke (from the valve's feedback), adopted when a dose starts.
#include <gtest/gtest.h>

#include "dynweigh/firmware/learned_valve_timing.hpp"

namespace dynweigh::firmware {
namespace {

constexpr double kBoreM = 0.06;

BasicLearnedValveTiming<double> valve(double dead_s = 0.030, double stroke_s = 0.080) {
  BasicLearnedValveTiming<double> v;
  v.configure({dead_s, stroke_s}, model::BeverlooMaterial<double>{}, kBoreM);
  return v;
}

TEST(LearnedValveTiming, OneSlowDoseIsNotEnoughTwoAre) {
  auto v = valve();
  v.learn_dead_time(0.055);
  v.start_dose();
  EXPECT_DOUBLE_EQ(v.in_use().dead_s, 0.030);
  v.learn_dead_time(0.055);
  v.start_dose();
  EXPECT_NEAR(v.in_use().dead_s, 0.055, 1e-12);
}

TEST(LearnedValveTiming, WithinTheValvesJitterTheDatasheetStands) {
  auto v = valve();
  for (int dose = 0; dose < 10; ++dose) v.learn_dead_time(0.034);  // 4 ms late, every dose
  v.start_dose();
  EXPECT_DOUBLE_EQ(v.in_use().dead_s, 0.030);
}

// A running mean over the last doses: one fast dose after many slow ones moves it by an eighth of
// the difference, not back to the datasheet.
TEST(LearnedValveTiming, RemembersTheLastFewDoses) {
  auto v = valve();
  for (int dose = 0; dose < 40; ++dose) v.learn_dead_time(0.060);
  v.learn_dead_time(0.030);
  v.start_dose();
  constexpr double kDosesRemembered = 8;  // docs/strategies.md
  EXPECT_NEAR(v.in_use().dead_s, 0.060 - 0.030 / kDosesRemembered, 1e-6);
}

TEST(LearnedValveTiming, ConfiguringForgetsWhatWasLearned) {
  auto v = valve();
  v.learn_dead_time(0.055);
  v.learn_dead_time(0.055);
  v.measured_travel(0.200, 4);
  v.configure({0.030, 0.080}, model::BeverlooMaterial<double>{}, kBoreM);
  v.start_dose();
  EXPECT_DOUBLE_EQ(v.in_use().dead_s, 0.030);
  EXPECT_DOUBLE_EQ(v.in_use().stroke_s, 0.080);
}

// The feedback times command to end position; the stroke is that less the dead time in use.
TEST(LearnedValveTiming, TheStrokeComesFromTheFeedbackOnceClearlyOff) {
  auto v = valve();
  v.measured_travel(0.030 + 0.150, 3);
  v.start_dose();
  EXPECT_NEAR(v.in_use().stroke_s, 0.150, 1e-12);

  v.measured_travel(0.030 + 0.090, 3);  // 10 ms off: within a jiffy and the dead time's error
  v.start_dose();
  EXPECT_DOUBLE_EQ(v.in_use().stroke_s, 0.080);

  v.measured_travel(0.010, 3);  // at the end position before the valve could move: an echo
  v.start_dose();
  EXPECT_DOUBLE_EQ(v.in_use().stroke_s, 0.080);
}

TEST(LearnedValveTiming, NothingLearnedTakesEffectWithinADose) {
  auto v = valve();
  v.start_dose();
  v.learn_dead_time(0.055);
  v.learn_dead_time(0.055);
  v.measured_travel(0.200, 4);
  EXPECT_DOUBLE_EQ(v.in_use().dead_s, 0.030);
  EXPECT_DOUBLE_EQ(v.in_use().stroke_s, 0.080);
}

// What a material's doses measured, kept in the settings record, comes back after a restart (which
// configures the timing anew): the next dose is timed as the last one was, not by the datasheet.
TEST(LearnedValveTiming, WhatWasMeasuredComesBackAfterARestart) {
  auto v = valve();
  v.learn_dead_time(0.058);
  v.learn_dead_time(0.062);
  v.measured_travel(0.060 + 0.150, 5);
  const ValveTimingLearning kept = v.learned();
  EXPECT_FLOAT_EQ(kept.dead_s, 0.060f);
  EXPECT_EQ(kept.dead_doses, 2u);
  EXPECT_EQ(kept.travel_strokes, 5u);

  auto restarted = valve();
  restarted.restore(kept);
  restarted.measured_travel(0.0, 0);  // the feedback has timed no stroke since the restart
  restarted.start_dose();
  EXPECT_NEAR(restarted.in_use().dead_s, 0.060, 1e-6);
  EXPECT_NEAR(restarted.in_use().stroke_s, 0.150, 1e-6);
  // One more dose joins the mean as the third: the two restored count.
  restarted.learn_dead_time(0.030);
  EXPECT_NEAR(restarted.learned().dead_s, 0.050, 1e-6);
  // The feedback's strokes since the restart are newer than the stored travel: a restore keeps them.
  restarted.measured_travel(0.180, 1);
  restarted.restore(kept);
  restarted.start_dose();
  EXPECT_NEAR(restarted.in_use().stroke_s, 0.180 - restarted.in_use().dead_s, 1e-6);
}

// A material not yet dosed keeps what the valve showed with the last one; a timing no valve shows
// (a stored record gone wrong) is not taken.
TEST(LearnedValveTiming, NothingOrNonsenseRestoredLeavesTheTimingAsItWas) {
  auto v = valve();
  v.learn_dead_time(0.055);
  v.learn_dead_time(0.055);
  v.restore(ValveTimingLearning{});
  ValveTimingLearning wild;
  wild.dead_s = -0.5f;
  wild.dead_doses = 3;
  v.restore(wild);
  v.start_dose();
  EXPECT_NEAR(v.in_use().dead_s, 0.055, 1e-9);
  EXPECT_FALSE(sane(wild));
}

// Through the dead time the valve is still full open: every millisecond more of it lets a
// millisecond more of full flow through, and delays the stream's start as much.
TEST(LearnedValveTiming, ALongerDeadTimeLetsItsFullFlowThrough) {
  auto v = valve();
  v.start_dose();
  const DoseValveTiming<double> datasheet = v.in_use();
  v.learn_dead_time(0.055);
  v.learn_dead_time(0.055);
  v.start_dose();
  const DoseValveTiming<double> slow = v.in_use();
  EXPECT_NEAR(slow.full_closing_flow_s - datasheet.full_closing_flow_s, 0.025, 1e-9);
  EXPECT_NEAR(slow.opening_delay_s - datasheet.opening_delay_s, 0.025, 1e-9);
  EXPECT_NEAR(slow.full_closing_duration_s, 0.055 + 0.080, 1e-12);
  EXPECT_NEAR(slow.half_closing_duration_s, 0.055 + 0.040, 1e-12);
  // A stroke lets part of the full flow through: less than the whole stroke's worth, more than none.
  EXPECT_GT(datasheet.full_closing_flow_s, 0.030);
  EXPECT_LT(datasheet.full_closing_flow_s, 0.030 + 0.080);
  EXPECT_GT(datasheet.half_flow_ratio, 0.0);
  EXPECT_LT(datasheet.half_flow_ratio, 1.0);
}

}  // namespace
}  // namespace dynweigh::firmware
