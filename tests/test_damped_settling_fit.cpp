// The settled weight from a platform's damped ringing (model/include/dynweigh/model/damped_settling_fit.hpp):
// against rings of known weight, decay and frequency in white noise, over many noise draws. A slow
// platform is the case the direct fit is for: the Prony fit alone does not certify its weight within
// the 64-sample window at all.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "dynweigh/model/damped_settling_fit.hpp"

namespace dynweigh::model {
namespace {

constexpr double kJiffyS = 0.01;
constexpr float kCertifiedErrorG = 1.5f;  // firmware/src/dosing_cycle.cpp's certification
constexpr int kDraws = 300;

struct Ring {
  double hz;
  double damping_ratio;
  double amplitude_g;
  double noise_g;
};

struct Outcome {
  double certifiable = 0;       // share whose standard error is within kCertifiedErrorG
  double within_error = 0;      // share off the truth by at most the standard error given
  double within_certified = 0;  // share off the truth by at most kCertifiedErrorG
  double mean_error_g = 0;
};

// `every_sample`: fitted after each sample, as the firmware certifies (each fit then starts from the
// last); else once, at the end.
Outcome fit_draws(const Ring& ring, int samples, bool every_sample = false) {
  Outcome o;
  for (int draw = 0; draw < kDraws; ++draw) {
    std::mt19937 generator(std::uint32_t(draw + 1));
    std::normal_distribution<double> noise(0.0, ring.noise_g);
    const double settled_g = 4000.0 + 3.7 * draw, phase = 0.7 * draw;
    const double omega = 2.0 * M_PI * ring.hz;
    DampedSettlingFit<float, 64> fit;
    for (int n = 0; n < samples; ++n) {
      const double t = n * kJiffyS;
      const double swing = ring.amplitude_g * std::exp(-ring.damping_ratio * omega * t) *
                           std::cos(omega * std::sqrt(1.0 - ring.damping_ratio * ring.damping_ratio) * t + phase);
      fit.push(float(settled_g + swing + noise(generator)));
      if (every_sample && n + 1 < samples) fit.fit();
    }
    const auto e = fit.fit();
    if (!e.valid) continue;
    const double error_g = double(e.final_value) - settled_g;
    o.certifiable += e.standard_error <= kCertifiedErrorG;
    o.within_error += std::fabs(error_g) <= double(e.standard_error);
    o.within_certified += std::fabs(error_g) <= double(kCertifiedErrorG);
    o.mean_error_g += error_g;
  }
  o.certifiable /= kDraws;
  o.within_error /= kDraws;
  o.within_certified /= kDraws;
  o.mean_error_g /= kDraws;
  return o;
}

void print(const char* name, int samples, const Outcome& o) {
  std::printf("%s, %d samples: certifiable %.3f, within its error %.3f, within 1.5 g %.3f, mean error %+.3f g\n", name,
              samples, o.certifiable, o.within_error, o.within_certified, o.mean_error_g);
}

// Certifiable in at least `least_certifiable` of the draws, the result within 1.5 g of the truth in
// 99 % and within its own error in 95 %, and no bias.
void expect_certified(const char* name, const Ring& ring, int samples, bool every_sample, double least_certifiable) {
  const Outcome o = fit_draws(ring, samples, every_sample);
  print(name, samples, o);
  EXPECT_GE(o.certifiable, least_certifiable) << name;
  EXPECT_GE(o.within_certified, 0.99) << name;
  EXPECT_GE(o.within_error, 0.95) << name;
  EXPECT_LE(std::fabs(o.mean_error_g), 0.1) << name;
}

// 5.5 Hz at 100 samples a second: 1 - c1 - c2 is about 0.1, and the Prony fit's error of W two
// to five times the noise over the window (it never reaches 1.5 g here).
TEST(DampedSettlingFit, CertifiesASlowPlatformWithinTwoPeriods) {
  expect_certified("5.5 Hz", Ring{5.5, 0.07, 40.0, 1.5}, 30, false, 0.95);
}

// As the firmware fits: after every sample, each fit one Gauss-Newton step from the last.
TEST(DampedSettlingFit, FittedEverySampleAsWell) {
  expect_certified("5.5 Hz, every sample", Ring{5.5, 0.07, 40.0, 1.5}, 30, true, 0.95);
}

// Past the window's 64 samples the oldest drop out, and the phases the last fit found are carried
// to the new oldest sample.
TEST(DampedSettlingFit, FollowsTheRingPastTheWindow) {
  const Ring slow{5.5, 0.03, 40.0, 1.5};
  for (int samples : {65, 100}) {
    const Outcome o = fit_draws(slow, samples, true);
    print("5.5 Hz, every sample", samples, o);
    EXPECT_GE(o.certifiable, 0.95) << samples;
    EXPECT_GE(o.within_certified, 0.99) << samples;
    EXPECT_LE(std::fabs(o.mean_error_g), 0.1) << samples;
  }
}

TEST(DampedSettlingFit, CertifiesANineHertzPlatformWithinTwoPeriods) {
  expect_certified("9 Hz", Ring{9.0, 0.05, 40.0, 1.5}, 20, false, 0.9);
}

// A stiff platform's ring is the Prony fit's own case: its estimate stands, as accurate as before.
TEST(DampedSettlingFit, AFastRingStaysWithinADivision) {
  const Ring fast{25.0, 0.05, 40.0, 1.5};
  const Outcome o = fit_draws(fast, 20);
  print("25 Hz", 20, o);
  EXPECT_DOUBLE_EQ(o.certifiable, 1.0);
  EXPECT_DOUBLE_EQ(o.within_certified, 1.0);
  EXPECT_LE(std::fabs(o.mean_error_g), 0.1);
}

// No ringing at all (a platform already at rest): the weight is the readings' mean, whichever fit
// gives it.
TEST(DampedSettlingFit, NoRingingGivesTheMean) {
  const Ring still{9.0, 0.05, 0.0, 1.0};
  const Outcome o = fit_draws(still, 40);
  print("no ring", 40, o);
  EXPECT_GE(o.within_certified, 0.99);
  EXPECT_LE(std::fabs(o.mean_error_g), 0.1);
}

// A window that drops its oldest samples fits what is left, as one that never saw them.
TEST(DampedSettlingFit, DroppedSamplesAreForgotten) {
  const Ring ring{9.0, 0.05, 40.0, 1.0};
  DampedSettlingFit<float, 64> all, later;
  std::mt19937 generator(7);
  std::normal_distribution<double> noise(0.0, ring.noise_g);
  for (int n = 0; n < 50; ++n) {
    const double t = n * kJiffyS, omega = 2.0 * M_PI * ring.hz;
    // The first ten samples carry a force that no ringing explains.
    const double extra_g = n < 10 ? 30.0 : 0.0;
    const float y = float(2500.0 + extra_g + ring.amplitude_g * std::exp(-ring.damping_ratio * omega * t) *
                                                 std::cos(omega * t) + noise(generator));
    all.push(y);
    if (n >= 10) later.push(y);
  }
  all.drop_oldest(10);
  EXPECT_EQ(all.count(), later.count());
  const auto dropped = all.fit(), fresh = later.fit();
  ASSERT_TRUE(dropped.valid);
  EXPECT_FLOAT_EQ(dropped.final_value, fresh.final_value);
  EXPECT_FLOAT_EQ(dropped.residual_rms, fresh.residual_rms);
  all.drop_oldest(100);
  EXPECT_EQ(all.count(), 0u);
}

TEST(DampedSettlingFit, TooFewSamplesGiveNoEstimate) {
  DampedSettlingFit<float, 64> fit;
  for (std::size_t n = 0; n + 1 < DampedSettlingFit<float, 64>::kMinimumSamples; ++n) fit.push(100.0f + float(n % 2));
  EXPECT_FALSE(fit.fit().valid);
}

}  // namespace
}  // namespace dynweigh::model
