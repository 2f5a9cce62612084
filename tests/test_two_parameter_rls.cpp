// The least squares behind the pac baseline's spill law (two_parameter_rls.hpp): from noisy
// synthetic fills it recovers a known spill law, and it stays a covariance through many fills that
// all excite one direction.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dynweigh/firmware/two_parameter_rls.hpp"

namespace dynweigh::firmware {
namespace {

// A plant's spill law the test knows: grams after the close at a flow Q in kg/s.
constexpr float kTrueK1 = 180.0f;
constexpr float kTrueK2 = 12.0f;
float true_spill_g(float q) { return kTrueK1 * q + kTrueK2 * q * q; }

TwoParameterRls pac_like_prior() {
  TwoParameterRls rls;
  rls.configure(0.9f, 5.0f);
  // A prior well off the truth: K1 a third low, K2 zero.
  rls.reset(120.0f, 0.0f, 60.0f, 20.0f);
  return rls;
}

TEST(TwoParameterRls, RecoversAKnownSpillLawFromNoisyFills) {
  TwoParameterRls rls = pac_like_prior();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> flow(0.5f, 4.0f);  // fills at various targets and flows
  std::normal_distribution<float> noise(0.0f, 3.0f);
  for (int fill = 0; fill < 60; ++fill) {
    const float q = flow(rng);
    EXPECT_TRUE(rls.update(q, q * q, true_spill_g(q) + noise(rng)));
  }
  EXPECT_NEAR(rls.state().theta1, kTrueK1, 0.05f * kTrueK1);
  EXPECT_NEAR(rls.state().theta2, kTrueK2, 0.2f * kTrueK2);
  for (float q : {0.5f, 2.0f, 4.0f}) EXPECT_NEAR(rls.predict(q, q * q), true_spill_g(q), 3.0f) << q;
}

TEST(TwoParameterRls, OneFlowLearnsTheSpillThereWithinAFewFills) {
  TwoParameterRls rls = pac_like_prior();
  std::mt19937 rng(11);
  std::normal_distribution<float> noise(0.0f, 3.0f);
  const float q = 2.4f;
  for (int fill = 0; fill < 4; ++fill) rls.update(q, q * q, true_spill_g(q) + noise(rng));
  EXPECT_NEAR(rls.predict(q, q * q), true_spill_g(q), 10.0f);
}

TEST(TwoParameterRls, ThousandsOfFillsAtOneFlowKeepACovariance) {
  TwoParameterRls rls = pac_like_prior();
  const float bound = std::fmax(rls.state().p11, rls.state().p22);
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.0f, 3.0f);
  const float q = 1.7f;
  for (int fill = 0; fill < 5000; ++fill) rls.update(q, q * q, true_spill_g(q) + noise(rng));
  EXPECT_TRUE(TwoParameterRls::sane(rls.state()));
  EXPECT_LE(rls.state().p11, bound * 1.0001f);
  EXPECT_LE(rls.state().p22, bound * 1.0001f);
  EXPECT_NEAR(rls.predict(q, q * q), true_spill_g(q), 6.0f);
  // And it still follows a change of the law.
  for (int fill = 0; fill < 40; ++fill) rls.update(q, q * q, true_spill_g(q) + 50.0f + noise(rng));
  EXPECT_NEAR(rls.predict(q, q * q), true_spill_g(q) + 50.0f, 6.0f);
}

TEST(TwoParameterRls, IgnoresAnObservationThatIsNotANumber) {
  TwoParameterRls rls = pac_like_prior();
  const TwoParameterRls::State before = rls.state();
  EXPECT_FALSE(rls.update(2.0f, 4.0f, std::nanf("")));
  EXPECT_FALSE(rls.update(INFINITY, 4.0f, 1.0f));
  EXPECT_EQ(rls.state().theta1, before.theta1);
  EXPECT_EQ(rls.state().p11, before.p11);
}

TEST(TwoParameterRls, RefusesToRestoreALawThatIsNoCovariance) {
  TwoParameterRls rls = pac_like_prior();
  TwoParameterRls::State bad{100.0f, 1.0f, 1.0f, 2.0f, 1.0f, 3};  // p12^2 > p11 p22
  EXPECT_FALSE(rls.restore(bad));
  EXPECT_EQ(rls.state().theta1, 120.0f);
  TwoParameterRls::State good{100.0f, 1.0f, 4.0f, 1.0f, 1.0f, 3};
  EXPECT_TRUE(rls.restore(good));
  EXPECT_EQ(rls.state().theta1, 100.0f);
}

}  // namespace
}  // namespace dynweigh::firmware
