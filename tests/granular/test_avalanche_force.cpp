// The avalanche force signal keeps momentum (zero net impulse) and its lumped parameters.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "dynweigh/granular/avalanche_force.hpp"
#include "dynweigh/granular/slope_sandpile_1d.hpp"
#include "dynweigh/granular/soc_calibration.hpp"

using namespace dynweigh::granular;

TEST(AvalancheForce, NetImpulseIsZeroAndAmplitudeIsGrainsPerWaveTimesWeight) {
  AvalancheForceModel model;
  model.grain_mass_kg = 2e-6;
  model.step_height_m = 1e-3;
  Avalanche a;
  a.size = 40;
  a.duration = 8;
  std::vector<double> force(2000, 0.0);
  const double dt = 1e-4;
  add_avalanche_force(a, 0.0123, model, dt, force);
  const double impulse = std::accumulate(force.begin(), force.end(), 0.0) * dt;
  const double expected_amplitude = 40.0 / 8.0 * 2e-6 * 9.81;
  const double dip_impulse = expected_amplitude * model.wave_period_s();
  EXPECT_NEAR(impulse, 0.0, 1e-9 * dip_impulse);
  EXPECT_NEAR(*std::min_element(force.begin(), force.end()), -expected_amplitude, 1e-12);
  EXPECT_NEAR(*std::max_element(force.begin(), force.end()), expected_amplitude, 1e-12);
  // The push comes duration waves after the dip.
  const auto first_push = std::find_if(force.begin(), force.end(), [](double f) { return f > 0; });
  const double push_time = static_cast<double>(first_push - force.begin()) * dt;
  EXPECT_NEAR(push_time, 0.0123 + 8 * model.wave_period_s(), dt);
}

TEST(SocCalibration, StaircaseGivesOneLargeAvalanchePerGrain) {
  // In the critical staircase every grain makes a system-wide avalanche: the critical mass is one
  // grain and F_a is one grain's weight (one grain per wave).
  constexpr int kColumns = 10;
  SlopeSandpile1d pile(kColumns, 2);
  for (int i = 0; i < 500; ++i) pile.add_grain(0);
  AvalancheForceModel model;
  model.grain_mass_kg = 1e-5;
  SocCalibrator calibrator(model, kColumns);
  for (int i = 0; i < 100; ++i) calibrator.record(pile.add_grain(0));
  const SocLumpedParameters p = calibrator.result();
  EXPECT_EQ(p.large_avalanches, 100);
  EXPECT_NEAR(p.critical_mass_kg, 1e-5, 1e-17);
  EXPECT_NEAR(p.avalanche_force_n, 1e-5 * model.gravity_m_s2, 1e-15);
  EXPECT_NEAR(p.avalanche_duration_s, (kColumns + 1) * model.wave_period_s(), 1e-12);
}
