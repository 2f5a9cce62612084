#pragma once
// The scale platform: a mass-spring-damper whose moving mass is the container plus its load, so
// its natural frequency drops as it fills. Stepped by the exact solution for a force held over the
// step (zero-order hold): with y the deflection from the equilibrium of that force,
// [y; v](t + dt) = exp(A dt) [y; v](t), A = [0 1; -k/m -c/m].
//
// exp(A dt) is a scaled-and-squared Taylor series of degree 10, in balanced coordinates
// (omega y, v): the matrix is halved until its norm is <= 1/4, so the truncation error is below
// (1/4)^11 / 11! = 6e-14 relative, at any frequency, damping or step (the squarings carry it to
// machine precision). Being the exact flow to that precision it is unconditionally stable and
// lets the oscillation energy only decay. It depends on the moving mass alone, so it is
// recomputed only when the mass changed (relative 1e-12): one sqrt and about 60 flops, through
// Cayley-Hamilton (exp(M) = a I + b M for a 2x2 M), no exp/sin/cos.
#include <cstdint>

#include "dynweigh/sim/scene.hpp"

namespace dynweigh::sim {

class ScalePlatform {
 public:
  ScalePlatform(const PlatformParameters& parameters, double g);

  // Applies `external_force_n` (weight of everything on it plus impact) over dt with the moving
  // mass `container + load_kg`.
  void step(double external_force_n, double load_kg, double dt);

  // Puts the platform at rest in the equilibrium of `force_n`.
  void rest_under(double force_n) {
    deflection_m_ = force_n / stiffness_n_m_;
    velocity_m_s_ = 0.0;
    support_force_n_ = force_n;
  }

  // What the load cell carries: spring and damper force.
  double support_force_n() const { return support_force_n_; }
  // Exact integral of the support force over the last step: F dt - m (v1 - v0).
  double last_support_impulse_n_s() const { return last_support_impulse_n_s_; }
  double deflection_m() const { return deflection_m_; }
  double velocity_m_s() const { return velocity_m_s_; }
  double stiffness_n_m() const { return stiffness_n_m_; }
  double damping_n_s_m() const { return damping_n_s_m_; }
  double container_kg() const { return parameters_.container_kg; }
  // Mechanical energy of the oscillation about the equilibrium of `external_force_n`.
  double oscillation_energy_j(double external_force_n, double load_kg) const;
  std::uint64_t steps() const { return steps_; }
  std::uint64_t transition_updates() const { return transition_updates_; }

 private:
  void update_transition(double mass_kg, double dt);

  PlatformParameters parameters_;
  double stiffness_n_m_;
  double damping_n_s_m_;
  double deflection_m_;
  double velocity_m_s_ = 0.0;
  double support_force_n_;
  double last_support_impulse_n_s_ = 0.0;
  // exp(A dt) for the cached mass and step, row major.
  double cached_mass_kg_ = -1.0;
  double cached_dt_ = -1.0;
  double phi_[4] = {1.0, 0.0, 0.0, 1.0};
  std::uint64_t steps_ = 0;
  std::uint64_t transition_updates_ = 0;
};

}  // namespace dynweigh::sim
