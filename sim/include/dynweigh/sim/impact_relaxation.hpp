#pragma once
// Landing grains disperse before they stop (thesis §1.3): the momentum they bring is handed to
// the scale through a first-order relaxation instead of a step. Momentum is conserved exactly:
// what enters the reservoir leaves it as force times time, whatever the step.
#include <cmath>
#include <cstdint>

namespace dynweigh::sim {

class ImpactRelaxation {
 public:
  explicit ImpactRelaxation(double relaxation_s) : relaxation_s_(relaxation_s) {}

  // Adds the momentum landed during a step of length dt and returns the mean force over it.
  // `landed_resting_n_s2` is the landed momentum weighted by the time left in the step after each
  // landing: a parcel landing late in the step has delivered less of its momentum by the step's
  // end. Its share is the chord of 1 - exp(-r / tau) between r = 0 and r = dt (error of order
  // (dt / tau)^2 in that share); with it left out the force would lag by up to a step.
  double force_over_step(double landed_momentum_n_s, double dt, double landed_resting_n_s2) {
    ++steps_;
    if (dt != cached_dt_) {
      cached_dt_ = dt;
      cached_share_ = relaxation_s_ > 0.0 ? -std::expm1(-dt / relaxation_s_) : 1.0;
    }
    const double delivered = reservoir_n_s_ * cached_share_ + landed_resting_n_s2 / dt * cached_share_;
    reservoir_n_s_ += landed_momentum_n_s - delivered;
    return delivered / dt;
  }

  double force_over_step(double landed_momentum_n_s, double dt) {
    ++steps_;
    if (dt != cached_dt_) {  // the share depends on dt only: one expm1 per run, not per step
      cached_dt_ = dt;
      cached_share_ = relaxation_s_ > 0.0 ? -std::expm1(-dt / relaxation_s_) : 1.0;
    }
    reservoir_n_s_ += landed_momentum_n_s;
    const double delivered = reservoir_n_s_ * cached_share_;
    reservoir_n_s_ -= delivered;
    return delivered / dt;
  }

  double stored_momentum_n_s() const { return reservoir_n_s_; }
  std::uint64_t steps() const { return steps_; }

 private:
  double relaxation_s_;
  double reservoir_n_s_ = 0.0;
  double cached_dt_ = -1.0;
  double cached_share_ = 1.0;
  std::uint64_t steps_ = 0;
};

}  // namespace dynweigh::sim
