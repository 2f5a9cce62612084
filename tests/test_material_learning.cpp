// What a model fill measured reaches the next fill of the same material: the open-time law and the
// measured close's residual (firmware/learned_fill_law.hpp), kept per material in the settings
// record. Each fill runs on a fresh plant with the indicator restarted from its stored record, as a
// plant that is switched off between fills.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <utility>
#include <vector>

#include "dynweigh/firmware/dose_plan.hpp"
#include "dynweigh/firmware/learned_fill_law.hpp"
#include "dynweigh/firmware/persistent_settings.hpp"
#include "dynweigh/firmware/settings_slots.hpp"
#include "dynweigh/hal/host/file_settings_store.hpp"
#include "dynweigh/model/oiml_r61_limits.hpp"
#include "dynweigh/sim/plant_family.hpp"
#include "support/console_session.hpp"
#include "support/temp_file.hpp"

namespace dynweigh::testing {
namespace {

using firmware::ParameterId;
using firmware::PersistentSettings;

// The settings as a restart finds them: through the stored record.
PersistentSettings after_power_cut(const PersistentSettings& settings) {
  std::vector<std::uint8_t> record(firmware::kSettingsRecordSize);
  EXPECT_EQ(firmware::encode_settings(settings, record.data(), record.size()), record.size());
  PersistentSettings restored;
  EXPECT_TRUE(firmware::decode_settings(record.data(), record.size(), restored));
  return restored;
}

// Fills of one target, back to back, each on a fresh plant; the errors by the plant's true mass, and
// (if asked) each fill's top-up pulses.
std::vector<double> fills(const sim::Scene& scene, PersistentSettings& settings, int target_g, int count,
                          const char* strategy = "model", std::vector<int>* topups = nullptr) {
  std::vector<double> errors;
  for (int k = 0; k < count; ++k) {
    ConsoleSession c(scene, std::uint64_t(100 + k), settings);
    c.idle(100);
    const double before_kg = c.session().plant().truth().static_kg;
    const auto lines = lines_of(c.run({"dose " + std::to_string(target_g) + " " + strategy}));
    EXPECT_EQ(lines.size(), 2u) << (lines.empty() ? "" : lines.front());
    if (topups && !lines.empty()) topups->push_back(std::atoi(field(lines.front(), "topups").c_str()));
    settings = after_power_cut(c.session().indicator().settings());
    errors.push_back((c.session().plant().truth().static_kg - before_kg) * 1000.0 - double(target_g));
  }
  return errors;
}

double x1_limit_g(double target_g) { return model::oiml_r61_x1_limits(target_g).initial_verification_g; }

PersistentSettings commissioned(const sim::Scene& scene) {
  PersistentSettings settings = hal::host::factory_settings(sim::Plant(scene, 1));
  settings.parameters.set(ParameterId::bore_mm, float(scene.silo.bore_m * 1000.0));
  settings.parameters.set(ParameterId::fall_mm, float(scene.column.fall_height_m * 1000.0));
  return settings;
}

// The default scene's flow fluctuates by 3 % rms: one 2 kg fill's scatter alone is about the X(1)
// limit. At 1 % what is left of an error is what the indicator knows, not the plant's noise.
void expect_second_fill_within_x1_with_density_off(double factor) {
  sim::Scene scene = sim::default_scene();
  scene.silo.fluctuation_rms = 0.01;
  PersistentSettings settings = commissioned(scene);
  settings.parameters.set(ParameterId::density, float(scene.silo.bulk_density * factor));
  const std::vector<double> errors = fills(scene, settings, 2000, 2);
  std::printf("density x%.1f, 2 kg: first %+.1f g, second %+.1f g\n", factor, errors[0], errors[1]);
  EXPECT_LE(std::abs(errors[1]), x1_limit_g(2000.0));
}

TEST(MaterialLearning, SecondTwoKilogramFillWithinX1WithTheDensityFortyPercentHigh) {
  expect_second_fill_within_x1_with_density_off(1.4);
}

TEST(MaterialLearning, SecondTwoKilogramFillWithinX1WithTheDensityFortyPercentLow) {
  expect_second_fill_within_x1_with_density_off(0.6);
}

// The valve is slower than the datasheet's defaults the indicator was left with: its let-through is
// larger than the model's, and a measured close ends over the target until a fill has taught it.
TEST(MaterialLearning, SecondTenKilogramFillWithinX1OnAValveOffItsDatasheet) {
  sim::Scene scene = sim::default_scene();
  scene.valve.dead_time_s = 0.070;
  scene.valve.full_stroke_s = 0.250;
  PersistentSettings settings = commissioned(scene);
  const std::vector<double> errors = fills(scene, settings, 10000, 2);
  std::printf("slow valve, 10 kg: first %+.1f g, second %+.1f g\n", errors[0], errors[1]);
  EXPECT_LE(std::abs(errors[1]), x1_limit_g(10000.0));
}

// A valve 40 ms slower to start and 170 ms slower in travel than the datasheet the indicator was left
// with. What its doses measured of it (the dead time from the first impacts, the travel from the
// feedback) is kept with the material, so the dose after a restart is timed by it, not by the
// datasheet again.
TEST(MaterialLearning, TheValvesMeasuredTimingSurvivesARestart) {
  sim::Scene scene = sim::default_scene();
  scene.valve.dead_time_s = 0.070;
  scene.valve.full_stroke_s = 0.250;
  PersistentSettings settings = commissioned(scene);
  fills(scene, settings, 5000, 2);
  const firmware::ValveTimingLearning& kept = settings.materials.at(0).learned.valve;
  EXPECT_EQ(kept.dead_doses, 2u);
  EXPECT_NEAR(kept.dead_s, 0.070, 0.012);
  EXPECT_GE(kept.travel_strokes, 1u);  // the strokes timed since the last restart
  EXPECT_NEAR(kept.travel_s, 0.070 + 0.250, 0.03);
  ConsoleSession c(scene, 200, settings);
  c.idle(100);
  const auto learned = lines_of(c.run({"estimates"}));
  ASSERT_EQ(learned.size(), 4u);  // LEARNED, VALVE, PULSES, OK
  ASSERT_EQ(learned[1].rfind("VALVE material=0 ", 0), 0u) << learned[1];
  EXPECT_NEAR(std::stod(field(learned[1], "dead_ms")), 70.0, 12.0) << learned[1];
  EXPECT_EQ(field(learned[1], "dead_doses"), "2") << learned[1];
  // The slowest dead time the feedback showed: the valve's 70 ms, its jitter and a jiffy's reading.
  const double slowest_dead_ms = std::stod(field(learned[1], "slowest_dead_ms"));
  EXPECT_GE(slowest_dead_ms, 70.0) << learned[1];
  EXPECT_LE(slowest_dead_ms, 90.0) << learned[1];
  EXPECT_NEAR(settings.materials.at(0).valve_slowest_dead_ms, slowest_dead_ms, 0.05);
  ASSERT_EQ(lines_of(c.run({"dose 5000"})).size(), 2u);
  const auto estimates = lines_of(c.run({"estimates"}));
  ASSERT_GE(estimates.size(), 1u);
  const double dead_used_ms = std::stod(field(estimates[0], "dead_used_ms"));
  const double stroke_used_ms = std::stod(field(estimates[0], "stroke_used_ms"));
  std::printf("after a restart: dead %.1f ms, stroke %.1f ms used (valve 70 / 250, datasheet 30 / 80)\n",
              dead_used_ms, stroke_used_ms);
  EXPECT_NEAR(dead_used_ms, 70.0, 12.0);
  EXPECT_NEAR(stroke_used_ms, 250.0, 30.0);
}

// The default scene through an 80 mm bore: about 5 kg/s, so that 500 g closes before its stream
// has landed.
sim::Scene wide_bore_scene() {
  sim::Scene scene = sim::default_scene();
  scene.silo.bore_m = 0.080;
  return scene;
}

// 500 g on a wide bore (about 5 kg/s) with 1.2 m of fall: more is in flight than the target, so the
// close comes before the stream has landed. The first two fills, on the prior, aim short and are
// topped up; the open-time law their closes teach times the later ones.
TEST(MaterialLearning, BlindSmallTargetWithinX1ByTheFourthFill) {
  sim::Scene scene = wide_bore_scene();
  PersistentSettings settings = commissioned(scene);
  settings.parameters.set(ParameterId::density, float(scene.silo.bulk_density * 1.3));
  const std::vector<double> errors = fills(scene, settings, 500, 5);
  std::printf("blind 500 g: %+.1f %+.1f %+.1f %+.1f %+.1f g\n", errors[0], errors[1], errors[2], errors[3], errors[4]);
  EXPECT_LE(std::abs(errors[3]), x1_limit_g(500.0));
  EXPECT_LE(std::abs(errors[4]), x1_limit_g(500.0));
}

TEST(MaterialLearning, AFaultedCycleTeachesNothing) {
  ConsoleSession c;
  c.run({"param dose_timeout_s 1"});  // the dose cannot finish: a fault ends it
  EXPECT_EQ(lines_of(c.run({"dose 10000"})).back(), "ERR 4 fault dose_timeout");
  EXPECT_TRUE(c.session().indicator().settings().materials.at(0).learned.empty());
}

// A close decided on a measured 3 kg/s stream after 3 s, predicted at 9 kg, the valve taken to let
// 40 ms through.
firmware::CloseRecord measured_close() {
  firmware::CloseRecord measured;
  measured.valid = true;
  measured.measured = true;
  measured.open_s = 3.0f;
  measured.flow_g_s = 3000.0f;
  measured.let_through_s = 0.04f;
  measured.prediction_g = 9000.0f;
  return measured;
}

// A close timed before the stream was measured, `open_s` after the open.
firmware::CloseRecord blind_close(float open_s) {
  firmware::CloseRecord blind;
  blind.valid = true;
  blind.open_s = open_s;
  return blind;
}

// The law's arithmetic alone, on fills of a known law: 3 kg/s, 150 g lost to the opening.
TEST(LearnedFillLaw, OneFillTeachesTheLawWhereItWasMadeAndAWildFillMovesTheLetThroughABoundedStep) {
  firmware::LearnedFillLaw law;
  law.configure(2000.0f, 0.05f);  // the prior: 2 kg/s, 50 ms
  firmware::CloseRecord blind = blind_close(0.5f);
  law.learn(blind, 3000.0f * 0.5f - 150.0f);
  EXPECT_NEAR(law.final_at_open_g(0.5f), 1350.0f, 5.0f);
  blind.open_s = 0.8f;
  law.learn(blind, 3000.0f * 0.8f - 150.0f);
  EXPECT_NEAR(law.final_at_open_g(1.2f), 3450.0f, 20.0f);  // two open times: the slope too

  firmware::CloseRecord measured = measured_close();
  law.learn(measured, 9000.0f + 0.06f * 3000.0f);  // the valve lets 60 ms more through
  EXPECT_NEAR(law.close_residual_s(0.04f), 0.06f, 1e-4f);
  measured.let_through_s = 0.10f;  // the next close used it
  law.learn(measured, 9000.0f - 3000.0f);  // a wild fill a second short
  EXPECT_NEAR(law.learned().close_let_through_s, 0.08f, 1e-4f);  // moved by the 20 ms bound only
  EXPECT_EQ(law.close_residual_s(0.075f), 0.0f);  // within 10 ms of the timing in use: it stands
}

// A fill whose line the law does not take (a flow outside a quarter to four times the prior's) leaves
// the law as it was; its open time still becomes the law's reach if the fill ended no higher than the
// law said there (a close timed that far ends short), never if it ended higher.
TEST(LearnedFillLaw, AFillTheLawDoesNotTakeExtendsItsReachOnlyIfItEndedShort) {
  firmware::LearnedFillLaw law;
  law.configure(6800.0f, 0.05f);  // the prior: 6.8 kg/s, 50 ms
  firmware::CloseRecord blind = blind_close(0.07f);
  law.learn(blind, 12.0f);  // a gate barely open
  ASSERT_TRUE(law.knows_open_time_law());
  EXPECT_FLOAT_EQ(law.longest_open_s(), 0.07f);
  const float at_150_ms = law.final_at_open_g(0.15f);
  const std::uint16_t fills = law.learned().open_time_law.fills;

  blind.open_s = 0.15f;
  law.learn(blind, 20.0f);  // the line through both: a fiftieth of the prior's flow
  EXPECT_EQ(law.learned().open_time_law.fills, fills) << "the law does not take it";
  EXPECT_FLOAT_EQ(law.final_at_open_g(0.15f), at_150_ms);
  EXPECT_FLOAT_EQ(law.longest_open_s(), 0.15f);

  blind.open_s = 0.3f;
  law.learn(blind, 50000.0f);  // far above the law: a flow no bore gives
  EXPECT_EQ(law.learned().open_time_law.fills, fills);
  EXPECT_FLOAT_EQ(law.longest_open_s(), 0.15f);
}

// The plan's uncertainty for a measured close is a model; the closes of a material show how far
// they really come out. Closes well within it narrow the next one's, wider ones widen it, each only
// as far as the last eight closes outweigh the model's own four, and to one and a half times it at most.
TEST(MeasuredCloseSpread, ClosesWithinTheirUncertaintyNarrowItAndWiderOnesWidenIt) {
  using firmware::MeasuredCloseSpread;
  MeasuredCloseSpread tight, wide, one;
  EXPECT_FLOAT_EQ(tight.sigma_scale(), 1.0f);  // nothing shown: the model's uncertainty
  for (int i = 0; i < 3; ++i) tight.add(i % 2 == 0 ? 0.3f : -0.3f);
  EXPECT_NEAR(tight.sigma_scale(), std::sqrt((4.0f + 3.0f * 0.09f) / 7.0f), 1e-5f);  // 0.78
  for (int i = 0; i < 20; ++i) tight.add(i % 2 == 0 ? 0.3f : -0.3f);
  EXPECT_NEAR(tight.sigma_scale(), std::sqrt((4.0f + 8.0f * 0.09f) / 12.0f), 1e-5f);  // 0.63: eight closes at most
  for (int i = 0; i < 20; ++i) wide.add(2.5f);
  EXPECT_FLOAT_EQ(wide.sigma_scale(), MeasuredCloseSpread::kHighestScale);
  one.add(40.0f);  // a wild close counts as three sigmas
  EXPECT_FLOAT_EQ(one.mean_square(), MeasuredCloseSpread::kLargestSquare);
  one.add(NAN);  // no close
  EXPECT_EQ(one.closes(), 1u);
  for (int i = 0; i < 30; ++i) tight.add(0.0f);
  EXPECT_NEAR(tight.sigma_scale(), std::sqrt(4.0f / 12.0f), 0.01f);  // however close they came out
  EXPECT_FALSE(one.restore(20.0f, 3));  // no close leaves more than 9
  EXPECT_EQ(one.closes(), 0u);
}

// Only a measured close teaches the spread, and only against the uncertainty the plan gave it; it
// comes back with the material.
TEST(LearnedFillLaw, MeasuredClosesTeachTheSpreadAgainstTheirPlansUncertainty) {
  firmware::LearnedFillLaw law;
  law.configure(3000.0f, 0.05f);
  firmware::CloseRecord measured = measured_close();
  firmware::CloseRecord blind = measured;
  blind.measured = false;
  law.learn(blind, 9400.0f, 50.0f);     // blind: the open-time law's, not the plan's measured sigma
  law.learn(measured, 9030.0f, 0.0f);   // no uncertainty given (the learn strategy plans nothing)
  EXPECT_EQ(law.learned().measured_closes.closes(), 0u);
  for (int i = 0; i < 8; ++i) law.learn(measured, 9000.0f + (i % 2 == 0 ? 10.0f : -10.0f), 50.0f);
  EXPECT_EQ(law.learned().measured_closes.closes(), 8u);
  EXPECT_NEAR(law.learned().measured_closes.mean_square(), 0.04f, 0.01f);  // 10 g of a 50 g sigma
  EXPECT_LT(law.measured_sigma_scale(), 0.65f);
  firmware::LearnedFillLaw restarted;
  restarted.configure(3000.0f, 0.05f);
  restarted.restore(law.learned());
  EXPECT_FLOAT_EQ(restarted.measured_sigma_scale(), law.measured_sigma_scale());
}

// The dose's plan gives its measured close an uncertainty and the certified close is measured
// against it: three 10 kg fills on the default scene, each closed on a measured stream, leave three
// closes in the material's spread, and `estimates` tells it.
TEST(MaterialLearning, EachMeasuredCloseTeachesTheSpreadAndEstimatesTellIt) {
  const sim::Scene scene = sim::default_scene();
  PersistentSettings settings = commissioned(scene);
  fills(scene, settings, 10000, 3);
  const firmware::MeasuredCloseSpread& spread = settings.materials.at(0).learned.measured_closes;
  EXPECT_EQ(spread.closes(), 3u);
  EXPECT_GT(spread.mean_square(), 0.0f);
  EXPECT_LT(spread.mean_square(), firmware::MeasuredCloseSpread::kLargestSquare);
  ConsoleSession c(scene, 1, settings);
  const auto estimates = lines_of(c.run({"estimates"}));
  ASSERT_FALSE(estimates.empty());
  EXPECT_NE(estimates.front().find(" measured_closes=3"), std::string::npos) << estimates.front();
  EXPECT_NE(estimates.front().find(" close_spread="), std::string::npos) << estimates.front();
  EXPECT_EQ(estimates.front().find(" close_spread=none"), std::string::npos) << estimates.front();
  std::printf("%s\n", estimates.front().c_str());
}

TEST(MaterialLearning, KeptPerMaterialAndForgottenByLearnReset) {
  const sim::Scene scene = sim::default_scene();
  PersistentSettings settings = commissioned(scene);
  fills(scene, settings, 2000, 1);
  const firmware::MaterialLearning& learned = settings.materials.at(0).learned;
  EXPECT_EQ(learned.open_time_law.fills, 1u);
  EXPECT_GT(settings.materials.at(0).valve_slowest_dead_ms, 0.0f);
  EXPECT_TRUE(settings.materials.at(1).learned.empty());
  ConsoleSession c(scene, 1, settings);
  // After a restart no dose has been measured, but what the material learned is told.
  const auto estimates = lines_of(c.run({"estimates"}));
  ASSERT_EQ(estimates.size(), 4u);  // LEARNED, VALVE, PULSES, OK
  EXPECT_EQ(estimates.front().rfind("LEARNED material=0 law_flow_kg_s=", 0), 0u) << estimates.front();
  EXPECT_NE(estimates.front().find(" law_fills=1 "), std::string::npos) << estimates.front();
  EXPECT_EQ(c.run({"learn reset"}), "OK\n");
  EXPECT_TRUE(c.session().indicator().settings().materials.at(0).learned.empty());
  EXPECT_EQ(c.session().indicator().settings().materials.at(0).valve_slowest_dead_ms, 0.0f);
}

}  // namespace
}  // namespace dynweigh::testing

namespace dynweigh::testing {
namespace {

firmware::MaterialLearning some_learning() {
  firmware::MaterialLearning learned;
  learned.open_time_law = {4200.0f, -310.0f, 9000.0f, -800.0f, 400.0f, 3};
  learned.close_let_through_s = 0.042f;
  learned.residual_fills = 2;
  learned.valve = {0.064f, 0.215f, 5, 9};
  learned.doses.add(0.1318f, 158.0f);
  learned.doses.add(0.24f, 808.0f);
  learned.doses.add(0.1824f, 415.0f);
  for (float error_sigmas : {0.5f, -0.4f, 0.6f}) learned.measured_closes.add(error_sigmas);
  return learned;
}

TEST(MaterialLearningRecord, SurvivesAPowerCutPerMaterial) {
  PersistentSettings settings;
  settings.materials.define(3);
  settings.materials.select(3, settings.parameters);
  settings.materials.keep_learned(some_learning());
  settings.materials.keep_valve_slowest_dead_ms(84.36f);
  const PersistentSettings restored = after_power_cut(settings);
  const firmware::MaterialLearning& kept = restored.materials.at(3).learned;
  EXPECT_FLOAT_EQ(restored.materials.at(3).valve_slowest_dead_ms, 84.4f);  // to 0.1 ms
  EXPECT_EQ(kept.open_time_law.fills, 3u);
  EXPECT_FLOAT_EQ(kept.open_time_law.theta1, 4200.0f);
  EXPECT_FLOAT_EQ(kept.open_time_law.theta2, -310.0f);
  EXPECT_FLOAT_EQ(kept.open_time_law.p12, -800.0f);
  EXPECT_FLOAT_EQ(kept.close_let_through_s, 0.042f);
  EXPECT_EQ(kept.residual_fills, 2u);
  EXPECT_FLOAT_EQ(kept.valve.dead_s, 0.064f);
  EXPECT_EQ(kept.valve.dead_doses, 5u);
  EXPECT_FLOAT_EQ(kept.valve.travel_s, 0.215f);
  EXPECT_EQ(kept.valve.travel_strokes, 9u);
  ASSERT_EQ(kept.doses.size(), 3u);
  EXPECT_EQ(kept.doses.entry(1).open_100us, 2400u);
  EXPECT_EQ(kept.doses.entry(1).final_g, 808u);
  EXPECT_EQ(kept.doses.next(), 3u);
  // The measured closes' spread is kept to 1/64 of a sigma in its root.
  EXPECT_EQ(kept.measured_closes.closes(), 3u);
  const float root = std::sqrt(some_learning().measured_closes.mean_square());
  EXPECT_NEAR(std::sqrt(kept.measured_closes.mean_square()), root, 0.5f / 64.0f);
  EXPECT_TRUE(restored.materials.at(0).learned.empty());
}

TEST(MaterialLearningRecord, WhatNoFillCanTeachIsDropped) {
  PersistentSettings settings;
  firmware::MaterialLearning wild = some_learning();
  wild.open_time_law.p11 = -1.0f;  // no covariance
  wild.close_let_through_s = 30.0f;   // half a minute of let-through
  wild.valve.travel_s = 4.0f;         // a valve four seconds in travel
  settings.materials.keep_learned(wild);
  const firmware::MaterialLearning kept = after_power_cut(settings).materials.at(0).learned;
  EXPECT_EQ(kept.open_time_law.fills, 0u);
  EXPECT_EQ(kept.residual_fills, 0u);
  EXPECT_TRUE(kept.valve.empty());
  EXPECT_EQ(kept.doses.size(), 3u);  // sane, so kept: each lesson is judged on its own
}

// A spread no close can leave (its root above three sigmas: each close counts at most as three) is
// dropped from a record; the rest of what was learned stays.
TEST(MaterialLearningRecord, AMeasuredCloseSpreadNoCloseCanLeaveIsDropped) {
  PersistentSettings settings;
  settings.materials.keep_learned(some_learning());
  std::vector<std::uint8_t> record(firmware::kSettingsRecordSize);
  ASSERT_EQ(firmware::encode_settings(settings, record.data(), record.size()), record.size());
  const std::size_t entry = firmware::kSettingsRecordSize - firmware::kMaterialTableBytes + 4;
  std::uint8_t* spread = record.data() + entry + firmware::kMaterialEntryBytesV6 + firmware::kRlsStateBytes + 6;
  ASSERT_EQ(spread[1], 3u);  // the closes, where the layout says
  spread[0] = 0xFF;          // a root of 4 sigmas
  auto put = [](std::uint8_t* p, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = std::uint8_t(v >> (8 * i));
  };
  put(record.data() + 12, firmware::crc32(record.data() + 16, record.size() - 16) ^ firmware::crc32(record.data(), 12));
  PersistentSettings loaded;
  ASSERT_TRUE(firmware::decode_settings(record.data(), record.size(), loaded));
  const firmware::MaterialLearning& kept = loaded.materials.at(0).learned;
  EXPECT_EQ(kept.measured_closes.closes(), 0u);
  EXPECT_FLOAT_EQ(kept.measured_closes.sigma_scale(), 1.0f);
  EXPECT_EQ(kept.open_time_law.fills, 3u);
  EXPECT_EQ(kept.residual_fills, 2u);
}

// The record of an older firmware: today's, with each material entry cut to what that version kept
// (version 6: name, density and class; version 7: also what the model's fills learned; version 8:
// also what its top-up pulses taught; version 9: also the valve's timing).
std::size_t older_entry_bytes(int version) {
  return version == 6   ? firmware::kMaterialEntryBytesV6
         : version == 7 ? firmware::kMaterialEntryBytesV7
         : version == 8 ? firmware::kMaterialEntryBytesV8
                        : firmware::kMaterialEntryBytesV9;
}
std::size_t older_record_bytes(int version) {
  return version == 6   ? firmware::kSettingsRecordSizeV6
         : version == 7 ? firmware::kSettingsRecordSizeV7
         : version == 8 ? firmware::kSettingsRecordSizeV8
                        : firmware::kSettingsRecordSizeV9;
}

std::vector<std::uint8_t> older_record(const PersistentSettings& settings, int version) {
  const std::size_t entry_bytes = older_entry_bytes(version);
  std::vector<std::uint8_t> now(firmware::kSettingsRecordSize);
  firmware::encode_settings(settings, now.data(), now.size());
  const std::size_t table = firmware::kSettingsRecordSize - firmware::kMaterialTableBytes;
  std::vector<std::uint8_t> old(now.begin(), now.begin() + std::ptrdiff_t(table + 4));
  for (std::size_t n = 0; n < firmware::MaterialTable::kMaterials; ++n) {
    const auto entry = now.begin() + std::ptrdiff_t(table + 4 + n * firmware::kMaterialEntryBytes);
    old.insert(old.end(), entry, entry + std::ptrdiff_t(entry_bytes));
  }
  EXPECT_EQ(old.size(), older_record_bytes(version));
  auto put = [](std::uint8_t* p, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = std::uint8_t(v >> (8 * i));
  };
  old[4] = std::uint8_t(version);
  put(old.data() + 8, std::uint32_t(old.size()));
  put(old.data() + 12, firmware::crc32(old.data() + 16, old.size() - 16) ^ firmware::crc32(old.data(), 12));
  return old;
}

firmware::TopUpPulseLearning some_pulses() {
  firmware::TopUpPulseLearning pulses;
  pulses.full = {{2300.0f, 55.0f, 40000.0f, -900.0f, 300.0f, 4}, 2500.0f, 0.08f, 4};
  pulses.half = {{900.0f, 20.0f, 9000.0f, -200.0f, 80.0f, 2}, 1000.0f, 0.04f, 2};
  return pulses;
}

// What the top-up pulses taught is kept per material and survives a power cut; a version-7 record
// (before it was kept) loads with the fills' lessons and no pulses'.
TEST(MaterialLearningRecord, ThePulsesLessonsSurviveAPowerCutAndAVersionSevenRecordHasNone) {
  PersistentSettings settings;
  settings.materials.keep_learned(some_learning());
  settings.materials.keep_pulses(some_pulses());
  const firmware::TopUpPulseLearning kept = after_power_cut(settings).materials.at(0).pulses;
  EXPECT_FLOAT_EQ(kept.full.law.theta1, 2300.0f);
  EXPECT_FLOAT_EQ(kept.full.law.theta2, 55.0f);
  EXPECT_FLOAT_EQ(kept.full.law.p12, -900.0f);
  EXPECT_FLOAT_EQ(kept.half.travel_s, 0.04f);
  EXPECT_EQ(kept.half.pulses, 2u);
  const std::vector<std::uint8_t> old = older_record(settings, 7);
  PersistentSettings loaded;
  ASSERT_TRUE(firmware::decode_settings(old.data(), old.size(), loaded));
  EXPECT_EQ(loaded.materials.at(0).learned.open_time_law.fills, some_learning().open_time_law.fills);
  EXPECT_TRUE(loaded.materials.at(0).pulses.empty());
  settings.materials.forget_learned();
  EXPECT_TRUE(settings.materials.at(0).pulses.empty());
}

// A version-8 record (before the valve's timing was kept) loads with the fills' and the pulses'
// lessons and no valve timing: the next dose starts from the datasheet.
TEST(MaterialLearningRecord, AVersionEightRecordLoadsWithNoValveTiming) {
  PersistentSettings settings;
  settings.materials.keep_learned(some_learning());
  settings.materials.keep_pulses(some_pulses());
  const std::vector<std::uint8_t> old = older_record(settings, 8);
  PersistentSettings loaded;
  ASSERT_TRUE(firmware::decode_settings(old.data(), old.size(), loaded));
  const firmware::MaterialLearning& learned = loaded.materials.at(0).learned;
  EXPECT_EQ(learned.open_time_law.fills, some_learning().open_time_law.fills);
  EXPECT_EQ(learned.residual_fills, some_learning().residual_fills);
  EXPECT_FLOAT_EQ(loaded.materials.at(0).pulses.full.law.theta1, some_pulses().full.law.theta1);
  EXPECT_TRUE(learned.valve.empty());
}

TEST(MaterialLearningRecord, AVersionSixRecordLoadsWithNothingLearned) {
  PersistentSettings settings;
  settings.materials.rename(2, "barley");
  settings.materials.set_density(2, 640.0f);
  settings.materials.keep_learned(some_learning());
  const std::vector<std::uint8_t> old = older_record(settings, 6);
  PersistentSettings loaded;
  ASSERT_TRUE(firmware::decode_settings(old.data(), old.size(), loaded));
  EXPECT_STREQ(loaded.materials.at(2).name, "barley");
  EXPECT_FLOAT_EQ(loaded.materials.at(2).density, 640.0f);
  for (std::size_t n = 0; n < firmware::MaterialTable::kMaterials; ++n) {
    EXPECT_TRUE(loaded.materials.at(n).learned.empty()) << n;
  }
}

// A record whose dose history no dose can leave (more doses than it holds, a slot out of range, a
// dose of no open time) loads with none; the rest of the material's lessons stand.
TEST(MaterialLearningRecord, ADoseHistoryNoDoseCanLeaveIsDropped) {
  PersistentSettings settings;
  settings.materials.keep_learned(some_learning());
  std::vector<std::uint8_t> record(firmware::kSettingsRecordSize);
  firmware::encode_settings(settings, record.data(), record.size());
  const std::size_t history = firmware::kSettingsRecordSize - firmware::kMaterialTableBytes + 4 +
                              firmware::kMaterialEntryBytesV9;
  // The record with these bytes of the first material's history changed, its CRC made good again.
  auto load_with = [&](std::initializer_list<std::pair<std::size_t, std::uint8_t>> changes) {
    std::vector<std::uint8_t> bad = record;
    for (const auto& [offset, value] : changes) bad[history + offset] = value;
    const std::uint32_t crc = firmware::crc32(bad.data() + 16, bad.size() - 16) ^ firmware::crc32(bad.data(), 12);
    for (int i = 0; i < 4; ++i) bad[12 + std::size_t(i)] = std::uint8_t(crc >> (8 * i));
    PersistentSettings loaded;
    EXPECT_TRUE(firmware::decode_settings(bad.data(), bad.size(), loaded));
    return loaded.materials.at(0).learned;
  };
  EXPECT_EQ(load_with({{0, 3}}).doses.size(), 3u);  // as written: the record itself is sound
  EXPECT_EQ(load_with({{0, 9}}).doses.size(), 0u);  // nine doses in eight slots
  EXPECT_EQ(load_with({{1, 8}}).doses.size(), 0u);  // the next slot out of range
  EXPECT_EQ(load_with({{1, 1}}).doses.size(), 0u);  // three doses, the next going into the second
  const firmware::MaterialLearning zero_open = load_with({{4, 0}, {5, 0}});  // the first dose's open time
  EXPECT_EQ(zero_open.doses.size(), 0u);
  EXPECT_EQ(zero_open.open_time_law.fills, 3u);
}

// The slowest dead time the valve's feedback showed sits in the two bytes behind the dose history's
// count and slot, which records before it left zero: none. One no valve shows (6.5 s) is none too,
// and the history beside it stays.
TEST(MaterialLearningRecord, TheSlowestDeadTimeNoValveShowsIsDroppedAndAnOlderRecordHasNone) {
  PersistentSettings settings;
  settings.materials.keep_learned(some_learning());
  settings.materials.keep_valve_slowest_dead_ms(95.0f);
  std::vector<std::uint8_t> record(firmware::kSettingsRecordSize);
  firmware::encode_settings(settings, record.data(), record.size());
  const std::size_t dead_time = firmware::kSettingsRecordSize - firmware::kMaterialTableBytes + 4 +
                                firmware::kMaterialEntryBytesV9 + 2;
  EXPECT_EQ(record[dead_time] | (record[dead_time + 1] << 8), 950);
  std::vector<std::uint8_t> bad = record;
  bad[dead_time] = bad[dead_time + 1] = 0xFF;
  const std::uint32_t crc = firmware::crc32(bad.data() + 16, bad.size() - 16) ^ firmware::crc32(bad.data(), 12);
  for (int i = 0; i < 4; ++i) bad[12 + std::size_t(i)] = std::uint8_t(crc >> (8 * i));
  PersistentSettings loaded;
  ASSERT_TRUE(firmware::decode_settings(bad.data(), bad.size(), loaded));
  EXPECT_EQ(loaded.materials.at(0).valve_slowest_dead_ms, 0.0f);
  EXPECT_EQ(loaded.materials.at(0).learned.doses.size(), 3u);
  const std::vector<std::uint8_t> old = older_record(settings, 9);
  PersistentSettings from_old;
  ASSERT_TRUE(firmware::decode_settings(old.data(), old.size(), from_old));
  EXPECT_EQ(from_old.materials.at(0).valve_slowest_dead_ms, 0.0f);
  EXPECT_EQ(from_old.materials.at(0).learned.open_time_law.fills, 3u);
}

// A version-9 record (before the last doses were kept) loads with the rest of what was learned and no
// dose history.
TEST(MaterialLearningRecord, AVersionNineRecordLoadsWithNoDoseHistory) {
  PersistentSettings settings;
  settings.materials.keep_learned(some_learning());
  const std::vector<std::uint8_t> old = older_record(settings, 9);
  PersistentSettings loaded;
  ASSERT_TRUE(firmware::decode_settings(old.data(), old.size(), loaded));
  const firmware::MaterialLearning& kept = loaded.materials.at(0).learned;
  EXPECT_EQ(kept.open_time_law.fills, 3u);
  EXPECT_EQ(kept.valve.travel_strokes, 9u);
  EXPECT_EQ(kept.doses.size(), 0u);
}

void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = std::uint8_t(v >> (8 * i));
}

std::vector<std::uint8_t> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A version-6, -7, -8 or -9 --nvm file (its settings slots smaller than today's, the logbook and the
// totalizers right behind them): grown on start, its logbook and totalizers moved behind today's
// slots, its settings read with what that version did not keep empty.
TEST(MaterialLearningRecord, AnOlderNvmFileKeepsItsSettingsLogbookAndTotals) {
  for (int version : {6, 7, 8, 9}) {
    SCOPED_TRACE("version " + std::to_string(version));
    PersistentSettings settings;
    settings.materials.rename(1, "barley");
    settings.materials.select(1, settings.parameters);
    settings.materials.keep_learned(some_learning());
    settings.materials.keep_pulses(some_pulses());
    firmware::MaterialTotals totals;
    totals.material[1].fills = 7;
    TempFile today{"dynweigh_learning"};
    {
      ASSERT_EQ(hal::host::prepare_nvm_file(today.path(), false), hal::host::NvmFile::created);
      hal::host::FileSettingsStore store(today.path());
      for (std::uint32_t seq = 1; seq <= 3; ++seq) {
        firmware::LogRecord r;
        r.target_dg = 3000;
        r.final_dg = 3000 + 10 * std::int32_t(seq);
        ASSERT_TRUE(store.logbook()->append(r));
      }
      ASSERT_TRUE(store.totalizers()->save(totals));
    }
    const std::vector<std::uint8_t> now = file_bytes(today.path());
    ASSERT_EQ(now.size(), hal::host::kNvmFileBytes);
    // Slot 0 holds the older record; slot 1 is erased; then today's logbook and totalizers.
    const std::size_t settings_bytes = version == 6   ? hal::host::kVersion6SettingsBytes
                                       : version == 7 ? hal::host::kVersion7SettingsBytes
                                       : version == 8 ? hal::host::kVersion8SettingsBytes
                                                      : hal::host::kVersion9SettingsBytes;
    std::vector<std::uint8_t> old(settings_bytes, 0xFF);
    const std::vector<std::uint8_t> record = older_record(settings, version);
    std::uint8_t* slot = old.data();
    put_u32(slot, 0x4C535744);  // "DWSL"
    put_u32(slot + 4, 5);
    put_u32(slot + 8, std::uint32_t(record.size()));
    std::copy(record.begin(), record.end(), slot + firmware::kSlotHeaderSize);
    put_u32(slot + 12, firmware::crc32(slot + 4, 8) ^ firmware::crc32(record.data(), record.size()));
    old.insert(old.end(), now.begin() + std::ptrdiff_t(hal::host::kFileLogbookOffset), now.end());
    ASSERT_EQ(old.size(), version == 6   ? hal::host::kVersion6FileBytes
                          : version == 7 ? hal::host::kVersion7FileBytes
                          : version == 8 ? hal::host::kVersion8FileBytes
                                         : hal::host::kVersion9FileBytes);
    TempFile file{"dynweigh_learning"};
    std::ofstream(file.path(), std::ios::binary).write(reinterpret_cast<const char*>(old.data()), std::streamsize(old.size()));

    EXPECT_EQ(hal::host::prepare_nvm_file(file.path(), false), hal::host::NvmFile::sized);
    EXPECT_EQ(file_bytes(file.path()).size(), hal::host::kNvmFileBytes);
    hal::host::FileSettingsStore store(file.path());
    PersistentSettings loaded;
    ASSERT_TRUE(store.load(loaded));
    EXPECT_STREQ(loaded.materials.at(1).name, "barley");
    EXPECT_EQ(loaded.materials.at(1).learned.empty(), version == 6);
    EXPECT_EQ(loaded.materials.at(1).pulses.empty(), version < 8);
    EXPECT_EQ(loaded.materials.at(1).learned.valve.empty(), version < 9);
    EXPECT_EQ(loaded.materials.at(1).learned.doses.size(), 0u);
    ASSERT_EQ(store.logbook()->last_sequence(), 3u);
    firmware::LogRecord r;
    ASSERT_TRUE(store.logbook()->read(3, r));
    EXPECT_EQ(r.final_dg, 3030);
    firmware::MaterialTotals kept;
    ASSERT_TRUE(store.totalizers()->load(kept));
    EXPECT_EQ(kept.material[1].fills, 7u);
  }
}

// A wide bore (about 5 kg/s) behind a slow gate (300 ms stroke) with 1.2 m of fall: the 500 g fills
// close with the gate half open, where the fill grows faster than linearly with the open time. The
// open-time law they teach, carried to 2 kg, would time a close too late; closed where the law's
// reach ends, the first 2 kg fill ends short and its top-up finishes it.
TEST(MaterialLearning, ALawTaughtOnShortClosesIsNotCarriedIntoAnOverdose) {
  sim::Scene scene = wide_bore_scene();
  scene.valve.full_stroke_s = 0.300;
  scene.silo.fluctuation_rms = 0.01;
  PersistentSettings settings = commissioned(scene);
  fills(scene, settings, 500, 2);
  const float longest_s = settings.materials.at(0).learned.law_longest_open_s;
  EXPECT_GT(longest_s, 0.0f);
  EXPECT_EQ(after_power_cut(settings).materials.at(0).learned.law_longest_open_s, longest_s);
  const std::vector<double> errors = fills(scene, settings, 2000, 1);
  std::printf("law taught to %.0f ms on 500 g, first 2 kg fill %+.1f g\n", 1000.0 * longest_s, errors[0]);
  EXPECT_LE(std::abs(errors[0]), x1_limit_g(2000.0));
}

// A family plant as the bench installs it (sim/plant_family.hpp): the geometry true, the density a
// guess, the platform and the valve at their defaults.
PersistentSettings family_commissioned(const sim::FamilyPlant& plant) {
  PersistentSettings settings = commissioned(plant.scene);
  const double container_mm = plant.scene.column.container_diameter_m * 1000.0;
  settings.parameters.set(ParameterId::container_mm, float(container_mm));
  settings.parameters.set(ParameterId::density, float(plant.density_guess));
  settings.parameters.set(ParameterId::platform_hz, firmware::Parameters{}.get(ParameterId::platform_hz));
  settings.parameters.set(ParameterId::platform_kg, firmware::Parameters{}.get(ParameterId::platform_kg));
  return settings;
}

// Plant 88 of the family of seed 202 (sim/plant_family.hpp), never tuned on: a 100 mm bore (4.4
// kg/s) behind a gate that takes 300 ms to open, a flow that starts at a third of itself, and a
// density guessed 37 % high. Its 500 g fills close blind after 70 to 150 ms, where the fill grows far
// faster than in proportion: the law's line through the second fill has a fifth of the prior's flow,
// which the law does not take. The reach must grow all the same: it stayed at 157 ms, every later
// dose closed there with about 105 g, and each 5 kg dose ended in a no_flow fault. Each 2 kg fill now
// carries it further, and the 5 kg fills are measured closes.
TEST(MaterialLearning, ShortClosesTheLawDoesNotTakeStillLetItReachFurther) {
  const sim::FamilyPlant plant = sim::draw_family_plant(202, 87);
  PersistentSettings settings = family_commissioned(plant);
  const auto reach_s = [&settings] { return settings.materials.at(0).learned.law_longest_open_s; };
  fills(plant.scene, settings, 500, 3);
  for (int k = 0; k < 2; ++k) {
    const float before_s = reach_s();
    fills(plant.scene, settings, 2000, 1);
    EXPECT_GT(reach_s(), 1.2f * before_s) << "2 kg fill " << k;
  }
  const std::vector<double> errors = fills(plant.scene, settings, 5000, 2);
  std::printf("law reaches %.0f ms; 5 kg fills %+.1f %+.1f g\n", 1000.0 * reach_s(), errors[0], errors[1]);
  for (double e : errors) EXPECT_LE(std::abs(e), x1_limit_g(5000.0));
}

// The same plant after a single 500 g fill: a 5 kg dose closes blind where the law's reach ends,
// 157 ms after the open, and brings about 100 g, under the 262 g of 5 kg's X(5) limit, where the
// law predicted some 330 g. That is the close doing what it meant (ending short for a top-up to
// finish), not a plant that delivers nothing: a result, never a no_flow fault.
TEST(MaterialLearning, ACloseAtTheLawsReachThatBringsItsShareIsNoNoFlow) {
  const sim::FamilyPlant plant = sim::draw_family_plant(202, 87);
  PersistentSettings settings = family_commissioned(plant);
  fills(plant.scene, settings, 500, 1);
  ASSERT_LT(settings.materials.at(0).learned.law_longest_open_s, 0.1f);
  ConsoleSession c(plant.scene, 7, settings);
  c.idle(100);
  const auto lines = lines_of(c.run({"dose 5000"}));
  ASSERT_EQ(lines.size(), 2u) << lines.front();
  EXPECT_EQ(lines.front().rfind("RESULT ", 0), 0u) << lines.front();
  EXPECT_EQ(lines.back(), "OK");
  std::printf("%s\n", lines.front().c_str());
}

// A 100 mm bore (8.7 kg/s by Beverloo) behind a gate that takes 300 ms to open: every 500 g and 1 kg fill
// closes with the gate part open, where the fill grows about as the cube of the open time. The first
// two 500 g fills (on the prior, then on a law of one point) aim short and are topped up; the law's
// line through them, carried to the third fill's longer open time, predicted too little: that fill
// came out 252 g over, and the first 1 kg fill 587 g over. The kept doses' curve
// (dose_history.hpp) times them short of the target instead.
TEST(MaterialLearning, TheKeptDosesCurveStopsTheLinesOverdose) {
  sim::Scene scene = wide_bore_scene();
  scene.silo.bore_m = 0.100;
  scene.valve.full_stroke_s = 0.300;
  PersistentSettings settings = commissioned(scene);
  const std::vector<double> small = fills(scene, settings, 500, 6);
  const std::size_t kept = settings.materials.at(0).learned.doses.size();
  const std::vector<double> larger = fills(scene, settings, 1000, 3);
  std::printf("500 g:");
  for (double e : small) std::printf(" %+.1f", e);
  std::printf(" g; then 1 kg:");
  for (double e : larger) std::printf(" %+.1f", e);
  std::printf(" g\n");
  EXPECT_EQ(kept, 6u);
  EXPECT_LE(small[2], 3.0 * x1_limit_g(500.0));
  EXPECT_LE(larger[0], 3.0 * x1_limit_g(1000.0));
  for (double e : small) EXPECT_LE(e, 10.0 * x1_limit_g(500.0));
  for (double e : larger) EXPECT_LE(e, 10.0 * x1_limit_g(1000.0));
}

// Three plants of the family of seed 101 (sim/plant_family.hpp), never tuned on: 3.2 to 6.3 kg/s
// behind gates of 160 to 200 ms, where a 500 g fill closes with the gate part open. The first fill,
// on the prior, closes after about 100 ms with 130 to 170 g and is topped up. The second is timed by
// the law that one close taught: its line, carried to about twice the open time, predicted too
// little, and the second fills came out 110, 118 and 163 g over. The curve through the one kept dose
// (dose_history.hpp) grows as the cube of the open time: the second close ends near or short of the
// target, and a top-up finishes it.
TEST(MaterialLearning, TheSecondBlindFillIsTimedByTheCubeThroughTheFirst) {
  for (std::uint32_t index : {45u, 79u, 170u}) {
    const sim::FamilyPlant plant = sim::draw_family_plant(101, index);
    PersistentSettings settings = family_commissioned(plant);
    const std::vector<double> errors = fills(plant.scene, settings, 500, 2);
    std::printf("plant %u of @101, 500 g: %+.1f then %+.1f g\n", index + 1, errors[0], errors[1]);
    EXPECT_LE(errors[1], 3.0 * x1_limit_g(500.0)) << "plant " << index + 1;
  }
}

// Four plants of the families of seeds 202 and 101, never tuned on: 3.2 to 9.7 kg/s behind gates of
// 110 to 255 ms with 5.5 to 8.4 ms of jitter, where a 500 g fill closes with the gate part open.
// Their first two fills, one on the prior and one on the cube through it, leave two doses whose
// fills differ by little against their open times (the valve's jitter and the flow's start-up
// outweigh what a few tens of milliseconds add there): the curve fitted to them, carried beyond
// the longer, grew too little, and the third fills came out 206, 124, 131 and 67 g over. Beyond the
// longer of two doses the curve now grows at least as the cube through it.
TEST(MaterialLearning, TheThirdBlindFillIsNotTimedByTwoDosesThatShowedLittleGrowth) {
  const std::pair<std::uint64_t, std::uint32_t> plants[] = {{202, 82}, {202, 106}, {202, 162}, {101, 178}};
  for (const auto& [seed, index] : plants) {
    const sim::FamilyPlant plant = sim::draw_family_plant(seed, index);
    PersistentSettings settings = family_commissioned(plant);
    const std::vector<double> errors = fills(plant.scene, settings, 500, 3);
    std::printf("plant %u of @%u, 500 g: %+.1f %+.1f %+.1f g\n", unsigned(index + 1), unsigned(seed), errors[0],
                errors[1], errors[2]);
    EXPECT_LE(errors[2], 3.0 * x1_limit_g(500.0)) << "plant " << index + 1 << " of @" << seed;
  }
}

// A new material's first dose is 500 g, its second 10 kg, on the three plants of
// TheSecondBlindFillIsTimedByTheCubeThroughTheFirst. The 10 kg dose is timed blind too, and the cube
// through the one kept dose reaches 10 kg only at several times that dose's open time; the law's
// reach, about twice it, comes first. The dose closes there, far short, and its three top-ups finish it
// within X(1), as before the cube.
TEST(MaterialLearning, ALargeDoseAfterOneSmallOneIsFinishedByItsTopUps) {
  for (std::uint32_t index : {45u, 79u, 170u}) {
    const sim::FamilyPlant plant = sim::draw_family_plant(101, index);
    PersistentSettings settings = family_commissioned(plant);
    fills(plant.scene, settings, 500, 1);
    const std::vector<double> errors = fills(plant.scene, settings, 10000, 1);
    std::printf("plant %u of @101: 10 kg after one 500 g fill %+.1f g\n", index + 1, errors[0]);
    EXPECT_LE(std::abs(errors[0]), x1_limit_g(10000.0)) << "plant " << index + 1;
  }
}

// The first 500 g of a new material through a 100 mm bore (8.7 kg/s by Beverloo) behind a gate that
// takes 300 ms to open, its datasheet stroke set true, the top-up switched off: the close comes before
// the stream can be weighed, on the prior, with the gate a small part open. The prior aims 2 sigmas of
// its 20 % short (the plan) and reckons what the partial stroke lets through. Reckoned as if the gate
// were full open (the prior before), the same close delivered 123 g of the 365 g aimed at.
TEST(MaterialLearning, TheFirstBlindCloseOfANewMaterialDeliversAboutWhatItAimedAt) {
  sim::Scene scene = wide_bore_scene();
  scene.silo.bore_m = 0.100;
  scene.valve.full_stroke_s = 0.300;
  scene.silo.fluctuation_rms = 0.01;
  PersistentSettings settings = commissioned(scene);
  settings.parameters.set(ParameterId::valve_stroke_ms, 300.0f);
  settings.parameters.set(ParameterId::topup_max, 0.0f);
  const double shares = firmware::DosePlanner::kSigmas * firmware::DosePlanner::kBlindShare;
  const double aim_g = (500.0 + x1_limit_g(500.0)) / (1.0 + shares);
  const double fill_g = 500.0 + fills(scene, settings, 500, 1)[0];
  std::printf("first 500 g on the prior, no top-up: %.1f g of the %.1f g aimed at\n", fill_g, aim_g);
  EXPECT_GT(fill_g, 0.6 * aim_g);
  EXPECT_LT(fill_g, 500.0);
}

// 500 g on a 5 kg/s stream that fluctuates 4 % rms: every close comes before the stream can be
// weighed, timed by the open-time law from the third fill on (14 fills). The law knows the mean fill, not
// this one's flow: the plan keeps aiming short of the target and topping up rather than trusting
// it to the class's limit.
TEST(MaterialLearning, LawTimedSmallFillsOfAFluctuatingStreamStayWithinX1) {
  sim::Scene scene = wide_bore_scene();
  scene.silo.fluctuation_rms = 0.04;
  PersistentSettings settings = commissioned(scene);
  const std::vector<double> errors = fills(scene, settings, 500, 14);
  // An overdose is what no top-up takes back: count those, and the worst.
  int over = 0;
  double worst_g = 0.0;
  for (std::size_t k = 2; k < errors.size(); ++k) {
    over += errors[k] > x1_limit_g(500.0) ? 1 : 0;
    worst_g = std::max(worst_g, errors[k]);
  }
  std::printf("500 g, 4 %% fluctuation:");
  for (double e : errors) std::printf(" %+.1f", e);
  std::printf(" g; %d of the 12 law-timed fills over X(1)\n", over);
  // Trusting the law to 1 % of the fill: 5 over, the worst +44 g.
  EXPECT_LE(over, 3);
  EXPECT_LE(worst_g, 3.0 * x1_limit_g(500.0));
}

// Three plants of the families of seeds 17, 3 and 13 (sim/plant_family.hpp), never tuned on,
// commissioned and dosed as the bench does (six fills of each target up to the one watched). Their 5
// and 10 kg fills close short on purpose and pulses finish them. The pulse before the last aimed for
// the class alone: at 0.8 of a deficit of some 70 g, where the cycle tops up a fill still 0.3 TL1
// short, so the last pulse followed most of the time, two or three pulses a fill. Weighing the
// second wait a last pulse costs, and the series' mean, it now finishes most fills itself, within
// X(1): fills 2 to 6 of the three took 37 pulses before, 29 now.
TEST(MaterialLearning, ThePulseBeforeTheLastFinishesMostFillsItself) {
  struct Watched {
    std::uint64_t seed;
    std::uint32_t index;
    int target_g;
  };
  int all_pulses = 0;
  for (const Watched& w : {Watched{17, 59, 5000}, Watched{3, 110, 10000}, Watched{13, 75, 5000}}) {
    const sim::FamilyPlant plant = sim::draw_family_plant(w.seed, w.index);
    PersistentSettings settings = family_commissioned(plant);
    for (int target_g : {500, 1000, 2000, 5000}) {
      if (target_g < w.target_g) fills(plant.scene, settings, target_g, 6);
    }
    std::vector<int> topups;
    const std::vector<double> errors = fills(plant.scene, settings, w.target_g, 6, "model", &topups);
    ASSERT_EQ(topups.size(), errors.size());
    std::printf("plant %u of @%u, %d g:", unsigned(w.index + 1), unsigned(w.seed), w.target_g);
    double mean_g = 0.0;
    int pulses = 0;
    for (std::size_t k = 1; k < errors.size(); ++k) {
      std::printf(" %+.1f g (%d)", errors[k], topups[k]);
      mean_g += errors[k] / double(errors.size() - 1);
      pulses += topups[k];
    }
    std::printf("; %d pulses over fills 2-6\n", pulses);
    const model::OimlR61Limits<double> x1 = model::oiml_r61_x1_limits(double(w.target_g));
    all_pulses += pulses;
    for (std::size_t k = 1; k < errors.size(); ++k) EXPECT_LE(std::abs(errors[k]), x1.initial_verification_g);
    EXPECT_LE(std::abs(mean_g), x1.in_service_g / 4.0);
  }
  EXPECT_LE(all_pulses, 31);
}

}  // namespace
}  // namespace dynweigh::testing
