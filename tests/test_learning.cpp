// The learn strategy's table of residual corrections (thesis §4.2).
#include <gtest/gtest.h>

#include <cmath>

#include "dynweigh/firmware/learning_table.hpp"
#include "support/console_session.hpp"

namespace dynweigh::testing {
namespace {

using firmware::LearningKey;
using firmware::LearningTable;

TEST(LearningTable, HalfTheErrorCappedAndADeadbandOfOneDivision) {
  LearningTable table;
  const LearningKey key = firmware::make_learning_key(10000, 1.05f, 2.4f);
  table.learn(key, 0.8f);  // within the deadband: nothing learned
  EXPECT_EQ(table.correction_g(key), 0.0f);
  table.learn(key, 30.0f);
  EXPECT_FLOAT_EQ(table.correction_g(key), 15.0f);
  table.learn(key, 1000.0f);  // one wild fill moves it by the cap only
  EXPECT_FLOAT_EQ(table.correction_g(key), 15.0f + LearningTable::kMaximumStepG);
  table.reset();
  EXPECT_EQ(table.correction_g(key), 0.0f);
}

TEST(LearningTable, KeysSeparateTargetsFallHeightsAndMaterials) {
  const LearningKey base = firmware::make_learning_key(10000, 1.05f, 2.4f);
  EXPECT_FALSE(base == firmware::make_learning_key(2000, 1.05f, 2.4f));
  EXPECT_FALSE(base == firmware::make_learning_key(10000, 0.80f, 2.4f));
  EXPECT_FALSE(base == firmware::make_learning_key(10000, 1.05f, 2.0f));
  EXPECT_TRUE(base == firmware::make_learning_key(10100, 1.06f, 2.41f));  // the same kind of fill
}

TEST(LearningTable, SurvivesARestartInTheSettingsRecord) {
  firmware::PersistentSettings settings;
  const LearningKey key = firmware::make_learning_key(5000, 1.1f, 1.0f);
  settings.learning.learn(key, -40.0f);
  std::uint8_t record[firmware::kSettingsRecordSize];
  ASSERT_EQ(firmware::encode_settings(settings, record, sizeof record), sizeof record);
  firmware::PersistentSettings restored;
  ASSERT_TRUE(firmware::decode_settings(record, sizeof record, restored));
  EXPECT_FLOAT_EQ(restored.learning.correction_g(key), -20.0f);
}

// The ideal scene removes the noise, so what is left of an error is what the model gets wrong.
sim::Scene material(double density_factor, double flow_factor) {
  sim::Scene scene = sim::ideal_scene();
  scene.silo.bulk_density *= density_factor;
  scene.silo.beverloo_C *= flow_factor;
  return scene;
}

TEST(LearnStrategy, ConvergesWithinTenFillsAfterAMaterialChange) {
  sim::Plant probe(sim::ideal_scene(), 1);
  firmware::PersistentSettings settings = hal::host::factory_settings(probe);
  settings.parameters.set(firmware::ParameterId::valve_dead_ms, 0.0f);
  settings.parameters.set(firmware::ParameterId::valve_stroke_ms, 0.0f);
  settings.parameters.set(firmware::ParameterId::pile_rise, 0.0f);
  auto fill = [&](const sim::Scene& scene) {
    ConsoleSession c(scene, 1, settings);
    c.idle(20);
    const auto lines = lines_of(c.run({"dose 6000 learn"}));
    EXPECT_EQ(lines.size(), 2u);
    settings = c.session().indicator().settings();
    return c.session().plant().truth().static_kg * 1000.0 - 6000.0;
  };
  for (int i = 0; i < 3; ++i) fill(material(1.0, 1.0));
  // A lighter, slower material the installer did not tell the indicator about.
  std::vector<double> errors;
  for (int i = 0; i < 10; ++i) errors.push_back(fill(material(0.7, 0.85)));
  std::printf("after the change: first fill %.1f g, tenth %.1f g\n", errors.front(), errors.back());
  EXPECT_GT(std::abs(errors.front()), 8.0);  // the model alone is measurably off
  EXPECT_LT(std::abs(errors.back()), std::max(2.5, std::abs(errors.front()) / 8.0));
}

// A small target closes before the stream can be measured, on the Beverloo prior, which cannot know
// the flow's start-up (alpha settling): the model is biased there, and learning removes the bias.
TEST(LearnStrategy, CorrectsACloseMadeOnThePrior) {
  firmware::PersistentSettings settings = hal::host::factory_settings(sim::Plant(sim::default_scene(), 1));
  std::vector<double> errors;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    ConsoleSession c(sim::default_scene(), seed, settings);
    c.idle(100);
    const double before = c.session().plant().truth().static_kg;
    EXPECT_EQ(lines_of(c.run({"dose 1000 learn"})).size(), 2u);
    settings = c.session().indicator().settings();
    errors.push_back((c.session().plant().truth().static_kg - before) * 1000.0 - 1000.0);
  }
  double late_mean = 0.0;
  for (std::size_t i = 6; i < errors.size(); ++i) late_mean += errors[i] / 6.0;
  std::printf("dose 1000 learn: first fill %+.1f g, mean of fills 7..12 %+.1f g\n", errors.front(), late_mean);
  EXPECT_LT(errors.front(), -60.0);  // the prior's bias, seen by the first fill
  EXPECT_LT(std::abs(late_mean), 30.0);
}

TEST(LearnStrategy, NeverLearnsFromAFaultedCycle) {
  ConsoleSession c;
  c.run({"param dose_timeout_s 1"});  // the dose cannot finish: a fault ends it
  EXPECT_EQ(lines_of(c.run({"dose 10000 learn"})).back(), "ERR 4 fault dose_timeout");
  EXPECT_EQ(c.run({"learn"}), "OK\n");  // the table is still empty
  for (std::size_t i = 0; i < LearningTable::kEntries; ++i) {
    EXPECT_FALSE(c.session().indicator().settings().learning.entry(i).used);
  }
}

TEST(LearnStrategy, LearnCommandListsAndResets) {
  ConsoleSession c;
  c.run({"dose 3000 learn"});
  const std::string listing = c.run({"learn"});
  EXPECT_EQ(listing.rfind("LEARN target_bucket=", 0), 0u) << listing;
  EXPECT_EQ(c.run({"learn reset"}), "OK\n");
  EXPECT_EQ(c.run({"learn"}), "OK\n");
  EXPECT_EQ(c.run({"learn forget"}), "ERR 2 usage: learn [reset]\n");
}

}  // namespace
}  // namespace dynweigh::testing
