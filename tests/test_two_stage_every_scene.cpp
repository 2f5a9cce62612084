// The twostage baseline on every shipped scene that doses into a container (a few seconds): from
// its defaults, after five learning fills, every fill within X(1) of the 5 and 10 kg targets (those
// the silo holds) at every band the bench sweeps. See test_two_stage_baseline.cpp.
#include <gtest/gtest.h>

#include "dynweigh/sim/scene.hpp"
#include "two_stage_judge.hpp"

namespace dynweigh::tools {
namespace {

class TwoStageEveryScene : public ::testing::TestWithParam<std::string> {};

TEST_P(TwoStageEveryScene, WithinX1AtEveryBandAfterFiveFills) {
  expect_within_x1_after_learning(BenchStrategy::twostage, GetParam());
}

std::vector<std::string> dosing_scenes() {
  std::vector<std::string> names;
  for (const auto& name : sim::scene_names()) {
    if (name != "hourglass") names.push_back(name);  // silo on the scale: nothing to dose
  }
  return names;
}

std::string test_name(const ::testing::TestParamInfo<std::string>& scene) {
  std::string name = scene.param;
  for (char& c : name) c = c == '-' ? '_' : c;
  return name;
}

INSTANTIATE_TEST_SUITE_P(Shipped, TwoStageEveryScene, ::testing::ValuesIn(dosing_scenes()), test_name);

}  // namespace
}  // namespace dynweigh::tools
