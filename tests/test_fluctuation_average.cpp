// The share of a flow's fluctuation its mean over a window keeps
// (model/include/dynweigh/model/fluctuation_average.hpp), against its limits, a value worked by
// hand, and the means of windows of a simulated Ornstein-Uhlenbeck process.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "dynweigh/model/fluctuation_average.hpp"

namespace dynweigh::model {
namespace {

TEST(FluctuationAverage, KeepsAllOfAShortWindowAndSqrtTwoTauOverTOfALongOne) {
  EXPECT_NEAR(fluctuation_share_of_window_mean(0.2, 1e-6), 1.0, 1e-5);
  EXPECT_NEAR(fluctuation_share_of_window_mean(0.2f, 1e-6f), 1.0f, 1e-5f);
  EXPECT_NEAR(fluctuation_share_of_window_mean(0.01, 100.0), std::sqrt(2.0 * 0.01 / 100.0), 1e-6);
  // tau = T: 2 exp(-1)
  EXPECT_NEAR(fluctuation_share_of_window_mean(0.5, 0.5), std::sqrt(2.0 * std::exp(-1.0)), 1e-9);
  EXPECT_DOUBLE_EQ(fluctuation_share_of_window_mean(0.2, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(fluctuation_share_of_window_mean(0.0, 0.5), 0.0);
  // Float and double agree where the series takes over from the closed form.
  for (float r : {0.05f, 1.0f, 9.0f, 10.0f, 11.0f, 200.0f}) {
    const double r_exact = double(r);
    const double exact = std::sqrt(2.0 * r_exact * (1.0 - r_exact * (1.0 - std::exp(-1.0 / r_exact))));
    EXPECT_NEAR(fluctuation_share_of_window_mean(r, 1.0f), exact, 1e-5) << r;
    EXPECT_NEAR(fluctuation_share_of_window_mean(r_exact, 1.0), exact, 1e-6) << r;
  }
  double previous = 1.0;
  for (double window_s = 0.01; window_s < 10.0; window_s *= 1.5) {
    const double share = fluctuation_share_of_window_mean(0.2, window_s);
    EXPECT_LT(share, previous) << window_s;  // a longer window averages more out
    previous = share;
  }
}

// The process the simulator's silo draws, exactly discretized: the rms of its means over windows
// of T, over many windows, is the share times its rms.
TEST(FluctuationAverage, MatchesTheMeansOfASimulatedProcess) {
  constexpr double kTau = 0.2, kStep = 0.001, kRms = 1.0;
  std::mt19937_64 random(7);
  std::normal_distribution<double> gaussian;
  const double decay = std::exp(-kStep / kTau), kick = kRms * std::sqrt(1.0 - decay * decay);
  for (double window_s : {0.1, 0.5, 1.5}) {
    const int steps = int(std::lround(window_s / kStep));
    double x = kRms * gaussian(random), sum_squares = 0.0;
    constexpr int kWindows = 4000;
    for (int w = 0; w < kWindows; ++w) {
      double sum = 0.0;
      for (int i = 0; i < steps; ++i) {
        x = x * decay + kick * gaussian(random);
        sum += x;
      }
      // windows back to back are correlated, but their variance is that of any one window
      sum_squares += (sum / steps) * (sum / steps);
    }
    const double measured = std::sqrt(sum_squares / kWindows);
    std::printf("window %.1f s: the means' rms %.3f, the share %.3f\n", window_s, measured,
                fluctuation_share_of_window_mean(kTau, window_s));
    EXPECT_NEAR(measured, fluctuation_share_of_window_mean(kTau, window_s), 0.04) << window_s;
  }
}

}  // namespace
}  // namespace dynweigh::model
