// The pac and flowpreact baselines as an integrator first meets them: installation values, every
// other parameter at its default and no trial fills. Four fills teach them their spill (or lag)
// and their timed close for targets reached before the flow is measured; after that every fill,
// judged by the plant's true mass, is within the OIML R61 X(1) initial-verification limit of its
// target where the display can weigh the stream before the close (10 kg on the default scene, 2 and
// 10 kg through the small-dose scene's 30 mm bore). At 2 kg on the default scene the close comes
// before the impact has passed the display filter: the fill is timed, and the silo's flow
// fluctuation over its 0.8 s (about 1.7 % rms) is what it cannot see; there it is within X(5).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>

#include "dynweigh/model/oiml_r61_class.hpp"
#include "dynweigh/sim/scene.hpp"
#include "fill_series.hpp"
#include "support/console_session.hpp"

namespace dynweigh::tools {
namespace {

constexpr std::uint32_t kLearningFills = 4;
constexpr std::uint32_t kJudgedFills = 4;

void expect_within_class_after_learning(BenchStrategy strategy, const std::string& scene_name, double target_g,
                                        double oiml_class) {
  Scenario scenario;
  scenario.name = scene_name;
  scenario.scene = *sim::scene_by_name(scene_name);
  const double limit = oiml_class * model::oiml_x1_limits(target_g).initial_verification_g;
  SeriesSpec spec;
  spec.strategy = strategy;
  spec.target_g = target_g;
  const auto errors = fills_from_defaults(spec, scenario, kLearningFills + kJudgedFills);
  std::string trace;
  for (double e : errors) trace += " " + std::to_string(std::lround(e));
  std::printf("%s %s %.0f g: errors%s g (X(%g): %.1f g)\n", bench_strategy_name(strategy), scene_name.c_str(),
              target_g, trace.c_str(), oiml_class, limit);
  for (std::size_t i = kLearningFills; i < errors.size(); ++i) {
    EXPECT_LE(std::abs(errors[i]), limit)  // a failed fill's NaN fails too
        << scene_name << " " << target_g << " g, fill " << i + 1 << ":" << trace;
  }
}

struct Case {
  BenchStrategy strategy;
  const char* scene;
  double target_g;
  double oiml_class;
};
void PrintTo(const Case& c, std::ostream* os) {
  *os << bench_strategy_name(c.strategy) << " " << c.scene << " " << c.target_g << " g";
}

class FlowBaselines : public ::testing::TestWithParam<Case> {};

TEST_P(FlowBaselines, WithinTheirClassAfterFourFills) {
  expect_within_class_after_learning(GetParam().strategy, GetParam().scene, GetParam().target_g,
                                     GetParam().oiml_class);
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  std::string name = std::string(bench_strategy_name(info.param.strategy)) + "_" + info.param.scene + "_" +
                     std::to_string(std::lround(info.param.target_g)) + "g";
  for (char& c : name) c = c == '-' ? '_' : c;
  return name;
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, FlowBaselines,
    ::testing::Values(Case{BenchStrategy::pac, "default", 10000.0, 1.0}, Case{BenchStrategy::pac, "default", 2000.0, 5.0},
                      Case{BenchStrategy::pac, "small-dose", 2000.0, 1.0},
                      Case{BenchStrategy::pac, "small-dose", 10000.0, 1.0},
                      Case{BenchStrategy::flowpreact, "default", 10000.0, 1.0},
                      Case{BenchStrategy::flowpreact, "default", 2000.0, 5.0},
                      Case{BenchStrategy::flowpreact, "small-dose", 2000.0, 1.0},
                      Case{BenchStrategy::flowpreact, "small-dose", 10000.0, 1.0}),
    case_name);

// A target far below what is in flight at full flow (50 g on the default scene: the stream lands
// half a second after the open, 2.4 kg/s): the valve opens once and closes once, a quarter stroke
// after its dead time (the valve's smallest dose, some 40 g) and long before the stream could be
// weighed, and never opens again; the fill ends in a result, never in a large overdose.
void expect_sound_tiny_fill(const char* strategy) {
  SCOPED_TRACE(strategy);
  testing::ConsoleSession c;
  c.idle(150);
  const std::size_t from = c.trace().size();
  const std::string answer = c.run({std::string("dose 50 ") + strategy});
  c.idle(100);
  int opens = 0, closes = 0, previous = 0;
  std::size_t open_row = 0, close_row = 0;
  for (std::size_t i = from; i < c.trace().size(); ++i) {
    const int valve = c.trace()[i].valve;
    if (valve != 0 && previous == 0) ++opens, open_row = i;
    if (valve == 0 && previous != 0) ++closes, close_row = i;
    previous = valve;
  }
  EXPECT_EQ(opens, 1) << answer;
  EXPECT_EQ(closes, 1) << answer;
  EXPECT_EQ(previous, 0) << "the valve must end closed";
  // Closed before the first grain could land (a fall of 1.2 m takes half a second).
  EXPECT_LT(close_row - open_row, 20u);
  const double delivered_g = (c.trace().back().static_kg - c.trace()[from].static_kg) * 1000.0;
  std::printf("%s, 50 g: open for %zu jiffies, %.1f g delivered: %s", strategy, close_row - open_row, delivered_g,
              answer.c_str());
  EXPECT_LT(delivered_g, 100.0) << answer;  // the valve's smallest dose, not a stream weighed too late
  EXPECT_NE(answer.find("RESULT"), std::string::npos) << answer;
}

TEST(FlowBaselinesTinyTarget, PacOpensOnceAndClosesAtOnce) { expect_sound_tiny_fill("pac"); }
TEST(FlowBaselinesTinyTarget, FlowPreactOpensOnceAndClosesAtOnce) { expect_sound_tiny_fill("flowpreact"); }

// What a fill taught them is in the settings (the record a restart reads); `learn reset` forgets it
// with the learn strategy's table, as for a new material.
TEST(FlowBaselinesLearning, AFillTeachesTheSettingsAndLearnResetForgetsIt) {
  testing::ConsoleSession c;
  c.idle(150);
  ASSERT_NE(c.run({"dose 2000 pac"}).find("RESULT"), std::string::npos);
  ASSERT_NE(c.run({"dose 6000 flowpreact"}).find("RESULT"), std::string::npos);
  const firmware::BaselineLearning& learned = c.session().indicator().settings().baselines;
  EXPECT_EQ(learned.pac.blind.fills, 1);
  EXPECT_EQ(learned.flowpreact.fills, 1);  // 6 kg: closed on the measured flow
  EXPECT_EQ(c.run({"learn reset"}), "OK\n");
  const firmware::BaselineLearning& forgotten = c.session().indicator().settings().baselines;
  EXPECT_EQ(forgotten.pac.blind.fills, 0);
  EXPECT_EQ(forgotten.flowpreact.fills, 0);
  EXPECT_EQ(forgotten.flowpreact.blind.fills, 0);
}

}  // namespace
}  // namespace dynweigh::tools
