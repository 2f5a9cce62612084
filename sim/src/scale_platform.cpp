#include "dynweigh/sim/scale_platform.hpp"

#include <cmath>

namespace dynweigh::sim {

ScalePlatform::ScalePlatform(const PlatformParameters& parameters, double g)
    : parameters_(parameters) {
  const double omega = 2.0 * M_PI * parameters.natural_hz;
  stiffness_n_m_ = parameters.container_kg * omega * omega;
  damping_n_s_m_ = 2.0 * parameters.damping_ratio * std::sqrt(stiffness_n_m_ * parameters.container_kg);
  deflection_m_ = parameters.container_kg * g / stiffness_n_m_;  // at rest under the empty container
  support_force_n_ = parameters.container_kg * g;
}

void ScalePlatform::step(double external_force_n, double load_kg, double dt) {
  if (parameters_.rigid) {
    support_force_n_ = external_force_n;
    return;
  }
  const double mass = parameters_.container_kg + load_kg;
  const double omega = std::sqrt(stiffness_n_m_ / mass);
  const double zeta = damping_n_s_m_ / (2.0 * std::sqrt(stiffness_n_m_ * mass));
  const double equilibrium = external_force_n / stiffness_n_m_;
  const double y0 = deflection_m_ - equilibrium;
  const double v0 = velocity_m_s_;
  double y = 0.0, v = 0.0;
  if (zeta < 1.0 - 1e-9) {
    const double omega_d = omega * std::sqrt(1.0 - zeta * zeta);
    const double decay = std::exp(-zeta * omega * dt);
    const double c = std::cos(omega_d * dt), s = std::sin(omega_d * dt);
    y = decay * (y0 * c + (v0 + zeta * omega * y0) / omega_d * s);
    v = decay * (v0 * c - (omega * omega * y0 + zeta * omega * v0) / omega_d * s);
  } else if (zeta > 1.0 + 1e-9) {
    const double root = omega * std::sqrt(zeta * zeta - 1.0);
    const double r1 = -zeta * omega + root, r2 = -zeta * omega - root;
    const double a = (v0 - r2 * y0) / (r1 - r2), b = y0 - a;
    const double e1 = std::exp(r1 * dt), e2 = std::exp(r2 * dt);
    y = a * e1 + b * e2;
    v = a * r1 * e1 + b * r2 * e2;
  } else {
    const double decay = std::exp(-omega * dt);
    y = decay * (y0 + (v0 + omega * y0) * dt);
    v = decay * (v0 - omega * (v0 + omega * y0) * dt);
  }
  deflection_m_ = equilibrium + y;
  velocity_m_s_ = v;
  support_force_n_ = stiffness_n_m_ * deflection_m_ + damping_n_s_m_ * velocity_m_s_;
}

double ScalePlatform::oscillation_energy_j(double external_force_n, double load_kg) const {
  const double y = deflection_m_ - external_force_n / stiffness_n_m_;
  const double mass = parameters_.container_kg + load_kg;
  return 0.5 * mass * velocity_m_s_ * velocity_m_s_ + 0.5 * stiffness_n_m_ * y * y;
}

}  // namespace dynweigh::sim
