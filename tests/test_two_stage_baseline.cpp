// The twostage baseline on the default scene, from its defaults (two_stage_judge.hpp); every other
// shipped scene in test_two_stage_every_scene.cpp.
#include "two_stage_judge.hpp"

namespace dynweigh::tools {
namespace {

TEST(TwoStageBaseline, WithinX1OnTheDefaultSceneAtEveryBandAfterFiveFills) {
  expect_within_x1_after_learning(BenchStrategy::twostage, "default");
}

TEST(TwoStageBaseline, DynamicallyCertifiedWithinX1OnTheDefaultSceneAtEveryBand) {
  expect_within_x1_after_learning(BenchStrategy::twostage_dyn, "default");
}

}  // namespace
}  // namespace dynweigh::tools
