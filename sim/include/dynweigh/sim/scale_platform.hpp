#pragma once
// The scale platform: a mass-spring-damper whose moving mass is the container plus its load, so
// its natural frequency drops as it fills. Stepped by the exact solution for a force held over the
// step (zero-order hold), so no step size can make it unstable.
#include "dynweigh/sim/scene.hpp"

namespace dynweigh::sim {

class ScalePlatform {
 public:
  ScalePlatform(const PlatformParameters& parameters, double g);

  // Applies `external_force_n` (weight of everything on it plus impact) over dt with the load mass.
  void step(double external_force_n, double load_kg, double dt);

  // What the load cell carries: spring and damper force.
  double support_force_n() const { return support_force_n_; }
  double deflection_m() const { return deflection_m_; }
  double velocity_m_s() const { return velocity_m_s_; }
  double stiffness_n_m() const { return stiffness_n_m_; }
  double container_kg() const { return parameters_.container_kg; }
  // Mechanical energy of the oscillation about the equilibrium of `external_force_n`.
  double oscillation_energy_j(double external_force_n, double load_kg) const;

 private:
  PlatformParameters parameters_;
  double stiffness_n_m_;
  double damping_n_s_m_;
  double deflection_m_;
  double velocity_m_s_ = 0.0;
  double support_force_n_;
};

}  // namespace dynweigh::sim
