#pragma once
// Landing grains disperse before they stop (thesis §1.3): the momentum they bring is handed to
// the scale through a first-order relaxation instead of a step. Momentum is conserved exactly:
// what enters the reservoir leaves it as force times time, whatever the step.
#include <cmath>

namespace dynweigh::sim {

class ImpactRelaxation {
 public:
  explicit ImpactRelaxation(double relaxation_s) : relaxation_s_(relaxation_s) {}

  // Adds the momentum landed during a step of length dt and returns the mean force over it.
  double force_over_step(double landed_momentum_n_s, double dt) {
    reservoir_n_s_ += landed_momentum_n_s;
    const double share = relaxation_s_ > 0.0 ? -std::expm1(-dt / relaxation_s_) : 1.0;
    const double delivered = reservoir_n_s_ * share;
    reservoir_n_s_ -= delivered;
    return delivered / dt;
  }

  double stored_momentum_n_s() const { return reservoir_n_s_; }

 private:
  double relaxation_s_;
  double reservoir_n_s_ = 0.0;
};

}  // namespace dynweigh::sim
