#include "dynweigh/sim/scale_platform.hpp"

#include <cmath>

namespace dynweigh::sim {
namespace {

constexpr int kTaylorDegree = 10;
// 1/k for the series, so the recurrence has no division on its dependency chain.
constexpr double kInverse[kTaylorDegree + 1] = {0.0, 1.0, 1.0 / 2, 1.0 / 3, 1.0 / 4, 1.0 / 5, 1.0 / 6,
                                                1.0 / 7, 1.0 / 8, 1.0 / 9, 1.0 / 10};
constexpr double kScaledNorm = 0.25;  // see scale_platform.hpp for the error bound
constexpr double kMassTolerance = 1e-12;

void multiply(const double a[4], const double b[4], double out[4]) {
  const double r0 = a[0] * b[0] + a[1] * b[2], r1 = a[0] * b[1] + a[1] * b[3];
  const double r2 = a[2] * b[0] + a[3] * b[2], r3 = a[2] * b[1] + a[3] * b[3];
  out[0] = r0, out[1] = r1, out[2] = r2, out[3] = r3;
}

}  // namespace

ScalePlatform::ScalePlatform(const PlatformParameters& parameters, double g) : parameters_(parameters) {
  const double omega = 2.0 * M_PI * parameters.natural_hz;
  stiffness_n_m_ = parameters.container_kg * omega * omega;
  damping_n_s_m_ = 2.0 * parameters.damping_ratio * std::sqrt(stiffness_n_m_ * parameters.container_kg);
  deflection_m_ = parameters.container_kg * g / stiffness_n_m_;  // at rest under the empty container
  support_force_n_ = parameters.container_kg * g;
}

void ScalePlatform::update_transition(double mass_kg, double dt) {
  ++transition_updates_;
  cached_mass_kg_ = mass_kg;
  cached_dt_ = dt;
  // Balanced coordinates z = (omega y, v) make A = [0 w; -w -c/m]: its norm is about omega dt
  // (0.08 for the default scene), so the series needs no squaring and few terms.
  const double inverse_mass = 1.0 / mass_kg;
  const double omega = std::sqrt(stiffness_n_m_ * inverse_mass);
  const double m01 = omega * dt, m10 = -omega * dt, m11 = -damping_n_s_m_ * inverse_mass * dt;
  const double norm = std::fabs(m10) + std::fabs(m11);
  int squarings = 0;
  for (double n = norm; n > kScaledNorm && squarings < 60; n *= 0.5) ++squarings;
  const double scale = std::ldexp(1.0, -squarings);
  // Cayley-Hamilton for a 2x2 M: M^2 = t M - d I, so M^k / k! = p_k I + q_k M with
  // p_{k+1} = -d q_k / (k+1) and q_{k+1} = (p_k + t q_k) / (k+1): exp(M) = a I + b M in a few
  // flops per term. Summed to kTaylorDegree terms (error bound in scale_platform.hpp).
  const double t = m11 * scale;                        // trace (m00 = 0)
  const double d = -(m01 * scale) * (m10 * scale);    // determinant (m00 = 0)
  double p = 1.0, q = 0.0, a = 1.0, b = 0.0;
  for (int k = 1; k <= kTaylorDegree; ++k) {
    const double inv = kInverse[k];
    const double p_next = -d * q * inv;
    q = (p + t * q) * inv;
    p = p_next;
    a += p;
    b += q;
  }
  double e[4] = {a, b * m01 * scale, b * m10 * scale, a + b * t};
  for (int i = 0; i < squarings; ++i) multiply(e, e, e);
  // Back to (y, v): phi = S^-1 E S with S = diag(omega, 1).
  phi_[0] = e[0];
  phi_[1] = e[1] * dt / m01;  // e[1] / omega
  phi_[2] = e[2] * omega;
  phi_[3] = e[3];
}

void ScalePlatform::step(double external_force_n, double load_kg, double dt) {
  ++steps_;
  if (parameters_.rigid) {  // the plant builds no platform for a rigid scale; kept for direct use
    support_force_n_ = external_force_n;
    last_support_impulse_n_s_ = external_force_n * dt;
    return;
  }
  const double mass = parameters_.container_kg + load_kg;
  if (dt != cached_dt_ || std::fabs(mass - cached_mass_kg_) > kMassTolerance * mass) update_transition(mass, dt);
  const double equilibrium = external_force_n / stiffness_n_m_;
  const double y0 = deflection_m_ - equilibrium;
  const double v0 = velocity_m_s_;
  const double y = phi_[0] * y0 + phi_[1] * v0;
  const double v = phi_[2] * y0 + phi_[3] * v0;
  deflection_m_ = equilibrium + y;
  velocity_m_s_ = v;
  support_force_n_ = stiffness_n_m_ * deflection_m_ + damping_n_s_m_ * velocity_m_s_;
  // Newton over the step: what the supports pushed is what the force pushed minus the gain in
  // the moving mass' momentum.
  last_support_impulse_n_s_ = external_force_n * dt - mass * (v - v0);
}

double ScalePlatform::oscillation_energy_j(double external_force_n, double load_kg) const {
  const double y = deflection_m_ - external_force_n / stiffness_n_m_;
  const double mass = parameters_.container_kg + load_kg;
  return 0.5 * mass * velocity_m_s_ * velocity_m_s_ + 0.5 * stiffness_n_m_ * y * y;
}

}  // namespace dynweigh::sim
