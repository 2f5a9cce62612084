#pragma once
// The force an avalanche puts on the scale (the thesis' F_a, example 3.2), with momentum kept.
// Each toppling drops one grain of mass m by one lattice step dh; it falls freely for
// tau = sqrt(2 dh / g) and is stopped by the pile. An avalanche of s topplings over D waves moves
// n = s / D grains per wave: while it runs, n grains are always in the air (the scale sees n m g
// less) and n grains land per tau (a momentum flux of n m sqrt(2 g dh) / tau = n m g more), which
// cancel. What remains is a dip of -n m g in the first wave and a push of +n m g in the wave
// after the last: the time integral of the force is zero, as it must be for a pile that starts and
// ends at rest. Its amplitude n m g is the avalanche force factor F_a.
#include <cmath>
#include <vector>

#include "dynweigh/granular/avalanche.hpp"

namespace dynweigh::granular {

struct AvalancheForceModel {
  double grain_mass_kg = 1e-6;    // mass of one lattice unit of grain
  double step_height_m = 0.5e-3;  // height of one lattice step (one grain diameter)
  double gravity_m_s2 = 9.81;     // standard gravity

  double wave_period_s() const { return std::sqrt(2.0 * step_height_m / gravity_m_s2); }
  double amplitude_n(const Avalanche& avalanche) const {
    if (avalanche.duration <= 0) return 0.0;
    return static_cast<double>(avalanche.size) / static_cast<double>(avalanche.duration) *
           grain_mass_kg * gravity_m_s2;
  }
  double duration_s(const Avalanche& avalanche) const {
    return static_cast<double>(avalanche.duration + 1) * wave_period_s();
  }
};

// Adds one avalanche starting at `start_s` to the sampled signal `force_n` (sample k covers
// [k dt, (k+1) dt)); contributions past the end of the signal are dropped. No allocation.
void add_avalanche_force(const Avalanche& avalanche, double start_s, const AvalancheForceModel& model,
                         double sample_period_s, std::vector<double>& force_n);

}  // namespace dynweigh::granular
