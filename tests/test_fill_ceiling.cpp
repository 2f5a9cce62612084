#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dynweigh/model/oiml_r61_class.hpp"
#include "dynweigh/sim/scene.hpp"
#include "fill_ceiling.hpp"

namespace dynweigh::tools {
namespace {

std::vector<double> normal_samples(double mean, double sigma, int n) {
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal(mean, sigma);
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(normal(random));
  return v;
}

// One pulse of 50 +- 10 g, a first close that always leaves 50 g: the fill ends within 10 g exactly
// as often as a normal variate lies within one sigma, and five such fills meet the steady class as
// often as five normal variates drawn afresh do. An ideal close too scattered to help changes nothing.
TEST(FillCeiling, OnePulseLandsAsOftenAsItsScatterAllows) {
  constexpr double kLimitG = 10.0, kBiasG = 3.75, kSigmaG = 10.0;
  CeilingActions actions;
  actions.pulses.push_back(normal_samples(50.0, kSigmaG, 4000));
  actions.blind.push_back(std::vector<double>(100, 450.0));
  actions.ideal_full_sigma_g = actions.ideal_half_sigma_g = 1e6;
  const FillCeiling c = fill_ceiling(actions, 500.0, {kLimitG, kBiasG}, 1, 5);
  EXPECT_NEAR(c.first, std::erf(kLimitG / kSigmaG / std::sqrt(2.0)), 0.03);
  std::mt19937_64 random(11);
  std::normal_distribution<double> normal(0.0, kSigmaG);
  int pass = 0;
  for (int s = 0; s < 20000; ++s) {
    double e[5], mean = 0.0, deviation = 0.0;
    for (double& x : e) mean += (x = normal(random)) / 5.0;
    for (double x : e) deviation = std::max(deviation, std::abs(x - mean));
    pass += deviation <= kLimitG && std::abs(mean) <= kBiasG;
  }
  EXPECT_NEAR(c.steady, pass / 20000.0, 0.03);
  // With no pulse left the close's 50 g deficit stands.
  EXPECT_EQ(fill_ceiling(actions, 500.0, {kLimitG, kBiasG}, 0, 5).first, 0.0);
}

// The plant's own pulses: a valve without jitter on a stream without fluctuation lands every fill;
// 10 ms of jitter at the same flow does not, and five fills in the class are rarer than one.
TEST(FillCeiling, TheValvesJitterIsWhatBoundsAPlantsFills) {
  sim::Scene scene = *sim::scene_by_name("default");
  scene.valve.dead_time_jitter_s = 0.0;
  scene.silo.fluctuation_rms = 0.0;
  const auto x1 = model::oiml_x1_limits(500.0);
  const CeilingLimits limits{x1.initial_verification_g, x1.in_service_g / 4.0};
  const FillCeiling steady_valve = fill_ceiling(sample_ceiling_actions(scene, 500.0, 8), 500.0, limits, 3, 5);
  EXPECT_GT(steady_valve.first, 0.99);
  EXPECT_GT(steady_valve.steady, 0.99);
  scene.valve.dead_time_jitter_s = 0.010;
  const FillCeiling jittery = fill_ceiling(sample_ceiling_actions(scene, 500.0, 40), 500.0, limits, 3, 5);
  EXPECT_LT(jittery.first, 0.95);
  EXPECT_LT(jittery.steady, jittery.first);
}

}  // namespace
}  // namespace dynweigh::tools
