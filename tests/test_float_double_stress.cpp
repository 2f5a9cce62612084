// Numerical stress of the firmware arithmetic: the float estimator and predictor the
// target runs beside the same code in double, over a day of jiffies, at full scale, at near-zero and
// at huge flow and under heavy noise. Both see the very same float samples, so every difference is
// the arithmetic's: the cutoff jiffies must agree and the predicted final differ by at most 0.5 d.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>

#include "dynweigh/firmware/model_cutoff.hpp"
#include "dynweigh/firmware/parameters.hpp"
#include "dynweigh/model/damped_settling_fit.hpp"
#include "dynweigh/sim/random.hpp"

namespace dynweigh::testing {
namespace {

constexpr double kDivisionG = 1.0;  // d of the default installation (stable band, learning deadband)
constexpr double kGravity = 9.81;

// What the scale reads while a stream lands: the static mass, the stream's momentum flux, the
// platform's 12 Hz ringing set off by the first impact, and Gaussian noise.
struct Stream {
  const char* name;
  std::uint64_t jiffies;
  double start_g;           // already on the scale (full-scale cases start high)
  double rate_g_per_jiffy;  // landing rate once the stream has arrived
  double noise_g;
  double ringing_g;
  float bore_mm = 60.0f;  // the installation: its Beverloo prior must not claim more than flows
  std::uint64_t arrival_jiffy = 50;
  double impact_speed_m_s = 4.8;
};

class StreamSamples {
 public:
  explicit StreamSamples(const Stream& s) : s_(s), random_(0x5eed) {}
  // The sample of jiffy j, rounded to the float the firmware receives.
  float at(std::uint64_t j) {
    double w = s_.start_g;
    if (j >= s_.arrival_jiffy) {
      const double landed_for = double(j - s_.arrival_jiffy);
      const double t = landed_for * 0.01;
      const double impulse_g = s_.rate_g_per_jiffy * 100.0 * s_.impact_speed_m_s / kGravity;
      w += s_.rate_g_per_jiffy * landed_for + impulse_g +
           s_.ringing_g * std::exp(-0.4 * t) * std::sin(2.0 * M_PI * 12.0 * t);
    }
    return float(w + s_.noise_g * random_.gaussian());
  }

 private:
  Stream s_;
  sim::Random random_;
};

struct SideBySide {
  std::uint64_t float_cutoff = 0, double_cutoff = 0;
  double max_prediction_difference_g = 0;
  double closest_call_g = 1e300;  // smallest |prediction - target| seen in double: how near a tie came
};

SideBySide run_side_by_side(const Stream& s, double target_g) {
  firmware::Parameters parameters;
  parameters.set(firmware::ParameterId::bore_mm, s.bore_mm);
  firmware::BasicModelCutoff<float> target_arithmetic;
  firmware::BasicModelCutoff<double> reference;
  target_arithmetic.configure(parameters);
  reference.configure(parameters);
  StreamSamples samples(s);
  const float start = samples.at(0);
  target_arithmetic.start(start);
  reference.start(double(start));
  SideBySide r;
  for (std::uint64_t j = 1; j < s.jiffies; ++j) {
    const float w = samples.at(j);
    const double by_float = double(target_arithmetic.observe(w));
    const double by_double = reference.observe(double(w));
    r.max_prediction_difference_g = std::fmax(r.max_prediction_difference_g, std::fabs(by_float - by_double));
    r.closest_call_g = std::fmin(r.closest_call_g, std::fabs(by_double - target_g));
    if (!r.float_cutoff && by_float >= target_g) r.float_cutoff = j;
    if (!r.double_cutoff && by_double >= target_g) r.double_cutoff = j;
  }
  return r;
}

void expect_agreement(const Stream& s) {
  // The fill that reaches the target ~90 % of the way through the stream.
  const double target_g = s.rate_g_per_jiffy * 0.9 * double(s.jiffies - s.arrival_jiffy) + 0.5;
  const SideBySide r = run_side_by_side(s, target_g);
  std::printf("%-16s %9llu jiffies: cutoff float %llu double %llu, max |float - double| %.4f g, "
              "closest call %.4f g\n",
              s.name, static_cast<unsigned long long>(s.jiffies), static_cast<unsigned long long>(r.float_cutoff),
              static_cast<unsigned long long>(r.double_cutoff), r.max_prediction_difference_g, r.closest_call_g);
  ASSERT_NE(r.double_cutoff, 0u) << s.name << ": the stream never reached its target";
  // Where a jiffy adds less than a few float steps of the target, float cannot tell which of two
  // jiffies first reaches it: near a tie the prediction wanders about the target with the noise
  // for a few jiffies, which at such a flow are worth less than 0.5 d together.
  const double float_step_g = double(std::nextafter(float(target_g), 1e30f) - float(target_g));
  const bool decidable = s.rate_g_per_jiffy > 8.0 * float_step_g;
  const double apart = std::fabs(double(r.float_cutoff) - double(r.double_cutoff));
  if (decidable) {
    EXPECT_EQ(r.float_cutoff, r.double_cutoff) << s.name;
  } else {
    EXPECT_LE(apart * s.rate_g_per_jiffy, 0.5 * kDivisionG) << s.name;
  }
  EXPECT_LE(r.max_prediction_difference_g, 0.5 * kDivisionG) << s.name;
}

TEST(FloatDoubleStress, ADayOfJiffiesFillingToFullScale) {
  // 50 kg (the default capacity) over 24 h through a 5 mm bore: 0.58 g/s, the same arithmetic for
  // 8.64 M jiffies.
  expect_agreement({"day_to_capacity", 8'640'000, 0.0, 50000.0 / 8'640'000.0, 0.3, 2.0, 5.0f});
}

TEST(FloatDoubleStress, FullScale) {
  expect_agreement({"full_scale", 3000, 45000.0, 24.0, 0.5, 40.0});  // tared 45 kg, fill to capacity
}

TEST(FloatDoubleStress, NearZeroFlow) {
  expect_agreement({"near_zero_flow", 60'000, 0.0, 0.01, 0.2, 0.5, 5.0f});  // 1 g/s for 10 min
}

TEST(FloatDoubleStress, HugeFlow) {
  expect_agreement({"huge_flow", 300, 0.0, 200.0, 1.0, 400.0});  // 20 kg/s
}

TEST(FloatDoubleStress, HeavyNoise) {
  expect_agreement({"heavy_noise", 800, 0.0, 24.0, 30.0, 300.0});
}

// The dynamic weighing fit at full scale: float and double estimates of the settled weight.
TEST(FloatDoubleStress, DynamicWeighingFitAtFullScale) {
  model::DampedSettlingFit<float, 64> target_arithmetic;
  model::DampedSettlingFit<double, 64> reference;
  sim::Random random(7);
  double worst = 0;
  for (double settled : {10.0, 5000.0, 49990.0}) {
    target_arithmetic.reset();
    reference.reset();
    for (int n = 0; n < 64; ++n) {
      const double t = 0.01 * n;
      const float w = float(settled + 30.0 * std::exp(-1.5 * t) * std::cos(2 * M_PI * 12.0 * t) + 0.3 * random.gaussian());
      target_arithmetic.push(w);
      reference.push(double(w));
    }
    const auto f = target_arithmetic.fit();
    const auto d = reference.fit();
    ASSERT_TRUE(f.valid && d.valid) << settled;
    worst = std::fmax(worst, std::fabs(double(f.final_value) - d.final_value));
    EXPECT_NEAR(d.final_value, settled, 1.0) << settled;
  }
  std::printf("dynamic weighing: max |float - double| %.4f g\n", worst);
  EXPECT_LE(worst, 0.5 * kDivisionG);
}

}  // namespace
}  // namespace dynweigh::testing
