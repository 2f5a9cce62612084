// A reading between a close and a top-up pulse only sizes the pulse (sizing_reading.hpp): three
// estimates agreeing within 2 g, with a standard error within 3 g, size it where the fill is short by
// more than it accepts plus that error; a result is always certified in full.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

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

// The jiffy, counted in the session's trace, in which a dose's answer first holds "RESULT ".
std::size_t result_jiffy(ConsoleSession& c, const std::string& command) {
  std::string answer = c.run({command}, 1);
  for (int i = 0; i < 20000 && answer.find("RESULT ") == std::string::npos; ++i) answer = c.run({}, 1);
  return c.trace().size();
}

// How soon a dose's first pulse follows its close, against how soon the same close is certified in
// full: the same plant and settings run twice, once with `topup_max 0` (no pulse may follow: the
// close's reading is the result), once with `allow_pulses` (a pulse follows). Jiffies from the dose
// command: the close (the valve shut) in either run, the first pulse's opening, the RESULT.
struct FirstPulseTiming {
  std::size_t close_alone = 0, close = 0, certified_in_full = 0, first_pulse = 0;
  double true_error_g = 0.0;
};

FirstPulseTiming time_first_pulse(std::uint64_t seed, const std::vector<std::string>& setup,
                                  const std::string& allow_pulses, const std::string& dose) {
  FirstPulseTiming t;
  ConsoleSession alone(sim::default_scene(), seed);
  alone.run(setup);
  alone.run({"param topup_max 0"});
  const std::size_t from_alone = alone.trace().size();
  t.certified_in_full = result_jiffy(alone, dose) - from_alone;
  t.close_alone = valve_spans(alone.trace(), from_alone).open.at(0).second - from_alone;
  ConsoleSession topped(sim::default_scene(), seed);
  topped.run(setup);
  topped.run({allow_pulses});
  const std::size_t from = topped.trace().size();
  const double before_kg = topped.session().plant().truth().static_kg;
  topped.run({dose});
  t.true_error_g = (topped.session().plant().truth().static_kg - before_kg) * 1000.0 - 2000.0;
  const ValveSpans s = valve_spans(topped.trace(), from);
  t.close = s.open.at(0).second - from;
  t.first_pulse = s.open.size() > 1 ? s.open[1].first - from : 0;
  return t;
}

// A 2 kg model fill on the default scene closes blind and aims short. The reading after its close
// only sizes the first pulse: the pulse opens at least two jiffies before that reading would have
// been certified in full (five estimates within 0.5 g; the valve opens in the jiffy after its
// reading, the RESULT line in the jiffy after that), and the fill still ends within X(1).
TEST(SizingReading, TheModelsFirstPulseComesBeforeItsReadingCouldBeCertifiedInFull) {
  for (std::uint64_t seed = 1; seed <= 2; ++seed) {
    const FirstPulseTiming t = time_first_pulse(seed, {}, "param topup_max 3", "dose 2000");
    ASSERT_EQ(t.close, t.close_alone) << "seed " << seed << ": the two runs must close alike";
    ASSERT_GT(t.first_pulse, t.close) << "seed " << seed;
    EXPECT_LE(t.first_pulse + 2, t.certified_in_full) << "seed " << seed;
    EXPECT_LE(std::fabs(t.true_error_g), model::oiml_r61_x1_limits(2000.0).initial_verification_g) << seed;
  }
}

// A baseline certified dynamically and topped up by `tol_action topup` (fixed `topup_ms` pulses while
// the fill is below the reject band) sizes its pulses on such readings too: preact closing 900 g
// early at 2 kg.
TEST(SizingReading, ABaselineToppedUpByTolActionPulsesSoonerToo) {
  const std::vector<std::string> setup = {"param preact_g 900", "param tol_action topup", "param topup_ms 60",
                                          "param certify dynamic"};
  for (std::uint64_t seed = 1; seed <= 2; ++seed) {
    const FirstPulseTiming t = time_first_pulse(seed, setup, "param topup_max 20", "dose 2000 preact");
    ASSERT_EQ(t.close, t.close_alone) << "seed " << seed;
    ASSERT_GT(t.first_pulse, t.close) << "seed " << seed;
    EXPECT_LE(t.first_pulse + 2, t.certified_in_full) << "seed " << seed;
    EXPECT_GE(t.true_error_g, -model::oiml_r61_x1_limits(2000.0).in_service_g) << "seed " << seed;
  }
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
  EXPECT_EQ(field(result, "topups"), "2") << result;  // one pulse ran the silo dry, the next moved nothing
  const double fill_g = (c.session().plant().truth().static_kg - before_kg) * 1000.0;
  EXPECT_NEAR(std::stod(field(result, "final")), fill_g, 1.5) << result;
  c.idle(50);
  EXPECT_EQ(c.session().plant().truth().stroke, 0.0);
}

// The jiffies of a 2 kg model dose on the default scene, from the rig's start: the close command,
// the valve's stroke back at zero after it, and the first pulse's opening.
struct DoseJiffies {
  std::uint32_t dose = 0, close_command = 0, close = 0, first_pulse = 0;
};

DoseJiffies time_a_two_kilogram_dose() {
  FaultRig dry(hal::host::SensorFaultPlan{}, hal::host::ValveFault::none, 0);
  dry.idle(100);
  DoseJiffies j;
  j.dose = dry.jiffy();
  dry.run_command("dose 2000", 1);
  bool opened = false;
  for (int i = 0; i < 2000 && j.first_pulse == 0; ++i) {
    const bool commanded_open = dry.step().valve != firmware::ValveCommand::closed;
    if (!commanded_open && opened && j.close_command == 0) j.close_command = dry.jiffy() - 1;
    const bool open = dry.plant().truth().stroke > 0.0;
    if (open && !opened && j.close != 0) j.first_pulse = dry.jiffy();
    if (!open && opened && j.close == 0) j.close = dry.jiffy();
    opened = open;
  }
  return j;
}

// The same dry silo on a load cell with no noise at all: after the pulse that moved nothing the
// reading still moves (the platform is still settling from the pulse before), and the dose ends in
// its RESULT as above, never in sensor_frozen (a hung converter is only told from a reading that
// does not move once while grains land).
TEST(SizingReading, ASiloRunDryOnANoiselessLoadCellIsNoFrozenReading) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    sim::Scene scene = scene_with_silo(1.5);
    scene.load_cell.noise_counts_rms = 0.0;
    ConsoleSession c(scene, seed);
    c.idle(20);
    const double before_kg = c.session().plant().truth().static_kg;
    const std::string out = c.run({"dose 2000"});
    const std::string result = out.substr(0, out.find('\n'));
    ASSERT_EQ(result.rfind("RESULT ", 0), 0u) << "seed " << seed << "\n" << out;
    EXPECT_EQ(field(result, "topups"), "2") << result;
    const double fill_g = (c.session().plant().truth().static_kg - before_kg) * 1000.0;
    EXPECT_NEAR(std::stod(field(result, "final")), fill_g, 1.5) << result;
  }
}

// A 2 kg model dose on the default scene whose load cell freezes at `freeze_jiffy` (counted from the
// rig's start, as time_a_two_kilogram_dose() counts): its answer, the valve openings after the first
// close, the plant's fill and the valve's stroke 50 jiffies after the answer.
struct FrozenDose {
  std::string answer;
  int pulses = 0;
  double fill_g = 0.0;
  double stroke_after = 0.0;
  bool fault_latched = false;
};

FrozenDose dose_frozen_at(std::uint32_t dose_jiffy, std::uint32_t freeze_jiffy) {
  hal::host::SensorFaultPlan freeze;
  freeze.fault = hal::host::SensorFault::freeze;
  freeze.at_jiffy = freeze_jiffy;
  FaultRig rig(freeze, hal::host::ValveFault::none, 0);
  rig.idle(100);
  EXPECT_EQ(rig.jiffy(), dose_jiffy);
  const double before_kg = rig.plant().truth().static_kg;
  FrozenDose d;
  rig.run_command("dose 2000", 1);
  bool opened = false, closed_once = false;
  for (int i = 0; i < 6000 && rig.output().find('\n') == std::string::npos; ++i) {
    rig.step();
    const bool open = rig.plant().truth().stroke > 0.0;
    if (open && !opened && closed_once) ++d.pulses;
    if (!open && opened) closed_once = true;
    opened = open;
  }
  d.answer = rig.output();
  d.fill_g = (rig.plant().truth().static_kg - before_kg) * 1000.0;
  rig.idle(50);
  d.stroke_after = rig.plant().truth().stroke;
  d.fault_latched = rig.run_command("dose 2000") == "ERR 4 fault active\n";
  return d;
}

// The load cell freezes in the jiffy the valve is told to close: the grains in flight land and the
// reading does not move once. No pulse is sized on it and no result reported: the dose ends in the fault.
TEST(SizingReading, AReadingThatDoesNotMoveWhileTheGrainsLandIsAFault) {
  const DoseJiffies j = time_a_two_kilogram_dose();
  ASSERT_GT(j.close, j.dose);
  const FrozenDose d = dose_frozen_at(j.dose, j.close_command);
  EXPECT_EQ(d.answer, "ERR 4 fault sensor_frozen\n");
  EXPECT_EQ(d.pulses, 0) << d.answer;
  EXPECT_EQ(d.stroke_after, 0.0) << d.answer;
  EXPECT_TRUE(d.fault_latched);
}

// The load cell freezes at the model's close, far short of the target: it moved once after the
// close, so one pulse is sized on the frozen reading. That pulse's grains land unseen: the dose ends
// in the fault, not in a result that is the reading before the pulse, and is not overdosed.
TEST(SizingReading, AReadingFrozenAtTheCloseEndsTheDoseAfterOnePulseInAFault) {
  const DoseJiffies j = time_a_two_kilogram_dose();
  ASSERT_GT(j.first_pulse, j.close) << j.close;
  const FrozenDose d = dose_frozen_at(j.dose, j.close);
  EXPECT_EQ(d.answer, "ERR 4 fault sensor_frozen\n");
  EXPECT_EQ(d.pulses, 1) << d.answer;
  EXPECT_LE(d.fill_g, 2000.0 + model::oiml_r61_x1_limits(2000.0).in_service_g) << d.answer;
  EXPECT_EQ(d.stroke_after, 0.0) << d.answer;
  EXPECT_TRUE(d.fault_latched);
}

}  // namespace
}  // namespace dynweigh::testing
