// The bench's oracle-scale limit (tools/bench/fill_series.cpp): a perfect scale that reads exactly
// what has landed and predicts what is in flight. Without disturbances it fills to the gram; under
// the default scene's flow fluctuation it can do no better than oracle, which reads what is in flight.
#include <gtest/gtest.h>

#include <cmath>

#include "dynweigh/sim/scene.hpp"
#include "fill_series.hpp"

namespace dynweigh::tools {
namespace {

Scenario scenario_named(const std::string& name) {
  const auto scene = sim::scene_by_name(name);
  EXPECT_TRUE(scene.has_value()) << name;
  Scenario scenario;
  scenario.name = name;
  if (scene) scenario.scene = *scene;
  return scenario;
}

SeriesResult series(BenchStrategy strategy, const Scenario& scenario, double target_g, std::uint32_t seeds) {
  SeriesSpec spec;
  spec.strategy = strategy;
  spec.target_g = target_g;
  return run_series(spec, scenario, seeds);
}

TEST(OracleScale, ParsesItsNameAndNoPrefix) {
  BenchStrategy strategy = BenchStrategy::model;
  ASSERT_TRUE(parse_bench_strategy("oracle-scale", strategy));
  EXPECT_EQ(strategy, BenchStrategy::oracle_scale);
  EXPECT_STREQ(bench_strategy_name(strategy), "oracle-scale");
  strategy = BenchStrategy::model;
  EXPECT_FALSE(parse_bench_strategy("oracle-scal", strategy));
  EXPECT_FALSE(parse_bench_strategy("oracle_scale", strategy));
  EXPECT_EQ(strategy, BenchStrategy::model);  // a rejected name leaves the strategy alone
  ASSERT_TRUE(parse_bench_strategy("oracle", strategy));
  EXPECT_EQ(strategy, BenchStrategy::oracle);
  ASSERT_TRUE(parse_bench_strategy("learn", strategy));  // the last of the names before oracle-scale
  EXPECT_EQ(strategy, BenchStrategy::learn);
}

TEST(OracleScale, IdealSceneFillsTenKilogramsWithinTwoGrams) {
  const SeriesResult r = series(BenchStrategy::oracle_scale, scenario_named("ideal"), 10000.0, 5);
  ASSERT_EQ(r.fills, 5u);
  ASSERT_EQ(r.failed, 0u);
  // Every fill's error lies within |bias| + max deviation of zero.
  EXPECT_LE(std::abs(r.bias_g) + r.max_deviation_g, 2.0) << "bias " << r.bias_g << " g, maxdev " << r.max_deviation_g;
  EXPECT_GT(r.time_ratio_mean, 0.9);
  EXPECT_LT(r.time_ratio_mean, 1.1);
}

TEST(OracleScale, DefaultSceneDeviatesNoLessThanOracle) {
  // It sees the stream only after its 0.45 s fall; oracle sees it leave the silo.
  const Scenario scenario = scenario_named("default");
  const SeriesResult scale = series(BenchStrategy::oracle_scale, scenario, 10000.0, 10);
  const SeriesResult oracle = series(BenchStrategy::oracle, scenario, 10000.0, 10);
  ASSERT_EQ(scale.failed, 0u);
  ASSERT_EQ(oracle.failed, 0u);
  EXPECT_GE(scale.max_deviation_g, oracle.max_deviation_g);
  EXPECT_GE(scale.sd_g, oracle.sd_g);
}

}  // namespace
}  // namespace dynweigh::tools
