// DEM calibration hooks: the flow factor alpha from the outflow speed profile across the
// orifice, and the impact relaxation time from the force on the container bottom.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "dynweigh/granular/impact_relaxation_estimate.hpp"
#include "dynweigh/granular/outflow_profile.hpp"

using namespace dynweigh::granular;

namespace {
// A load signal of the model: nothing before t0, then P (1 - exp(-(t - t0) / tau)) + b (t - t0),
// with a deterministic collision-like ripple of +-amplitude that grows in with the impact.
std::vector<double> model_load(const std::vector<double>& t, double t0, double p, double tau, double b, double ripple) {
  std::vector<double> load(t.size());
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double s = t[k] - t0;
    const double rise = 1.0 - std::exp(-s / tau);
    load[k] = s < 0 ? 0.0 : rise * (p + ripple * std::sin(977.0 * t[k]) * std::sin(31.0 * t[k])) + b * s;
  }
  return load;
}

std::vector<double> times(double dt, std::size_t n) {
  std::vector<double> t(n);
  for (std::size_t k = 0; k < n; ++k) t[k] = dt * static_cast<double>(k);
  return t;
}
}  // namespace

TEST(ImpactRelaxationEstimate, RecoversTheTimeConstantOfALandingStreamUnderWeightGrowthAndRipple) {
  const std::vector<double> t = times(2e-4, 20000);
  for (const double tau : {0.02, 0.05, 0.12}) {
    const std::vector<double> load = model_load(t, 0.50013, 2.0, tau, 3.0, 0.3);
    const ImpactRelaxationEstimate e = estimate_impact_relaxation(t, load);
    ASSERT_TRUE(e.valid) << tau;
    EXPECT_NEAR(e.relaxation_time, tau, 0.03 * tau) << tau;
    EXPECT_NEAR(e.step_force, 2.0, 0.03 * 2.0) << tau;
    EXPECT_NEAR(e.load_slope, 3.0, 0.05 * 3.0) << tau;
    EXPECT_NEAR(e.landing_time, 0.50013, 2e-4);
  }
}

TEST(ImpactRelaxationEstimate, ASteadyStepWithoutGrowthGivesItsTimeConstant) {
  const std::vector<double> t = times(1e-4, 20000);
  const std::vector<double> load = model_load(t, 0.30004, 5.0, 0.04, 0.0, 0.0);
  const ImpactRelaxationEstimate e = estimate_impact_relaxation(t, load);
  ASSERT_TRUE(e.valid);
  EXPECT_NEAR(e.relaxation_time, 0.04, 0.01 * 0.04);
  EXPECT_NEAR(e.load_slope, 0.0, 1e-9);
}

TEST(ImpactRelaxationEstimate, NoLandingIsNotAnEstimate) {
  const std::vector<double> t = times(1e-3, 100);
  EXPECT_FALSE(estimate_impact_relaxation(t, std::vector<double>(100, 0.0)).valid);
  EXPECT_FALSE(estimate_impact_relaxation(t, std::vector<double>(50, 1.0)).valid);  // sizes differ
}

TEST(OutflowProfile, AParabolicProfileGivesTheMeanToPeakRatioOfItsBins) {
  // Discs at the bin centres of a 10 d gap falling with v(x) = v0 (1 - u^2), u = (x - xc) / 5:
  // alpha = mean / peak over the bins = 1 - (N^2 - 1) / (3 N^2) with N = 10, about 2/3 as the
  // continuous parabola. Discs outside the band or the gap, and fixed discs, do not count.
  OutflowProfile profile = make_outflow_profile(20.0, 30.0, 0.0, 0.5, 10);
  Dem2dSettings settings;
  settings.gravity_y = 0;
  settings.domain_min_x = 0;
  settings.domain_max_x = 50;
  settings.domain_min_y = -5;
  settings.domain_max_y = 5;
  Dem2dWorld world(settings, 16);
  const double v0 = 2.0;
  for (int k = 0; k < 10; ++k) {
    DiscSpec d;
    d.x = 20.5 + k;
    d.y = 0.1 * ((k % 3) - 1);
    const double u = (d.x - 25.0) / 5.0;
    d.vy = -v0 * (1.0 - u * u);
    d.radius = 0.05;  // small: no contacts
    world.add_disc(d);
  }
  DiscSpec above;  // outside the band
  above.x = 25.0;
  above.y = 2.0;
  above.vy = -10.0;
  world.add_disc(above);
  DiscSpec aside = above;  // outside the gap
  aside.x = 35.0;
  aside.y = 0.0;
  world.add_disc(aside);
  DiscSpec wall = aside;  // fixed
  wall.x = 25.2;
  wall.fixed = true;
  world.add_disc(wall);
  sample_outflow(profile, world);
  sample_outflow(profile, world);
  const OutflowSummary s = summarize_outflow(profile);
  const double n = 10;
  EXPECT_DOUBLE_EQ(s.sampled_discs, 20.0);
  EXPECT_NEAR(s.peak_speed, v0 * (1.0 - 0.01), 1e-12);  // the two middle bins, u = +-0.1
  EXPECT_NEAR(s.mean_speed, v0 * (1.0 - (n * n - 1.0) / (3.0 * n * n)), 1e-12);
  EXPECT_NEAR(s.alpha, s.mean_speed / s.peak_speed, 1e-15);
  EXPECT_EQ(profile.samples, 2u);
}

TEST(OutflowProfile, SiloProfileSpansTheGapBetweenTheRemainingBottomDiscs) {
  // Peer silo, 8 discs removed: bottom discs 21..28 go, the gap runs from 20.5 to 28.5.
  const OutflowProfile p = make_silo2d_outflow_profile(50.0, 8, 16);
  EXPECT_DOUBLE_EQ(p.x_min, 20.5);
  EXPECT_DOUBLE_EQ(p.x_max, 28.5);
  EXPECT_EQ(p.speed_sum.size(), 16u);
}
