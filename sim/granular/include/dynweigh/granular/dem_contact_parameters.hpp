#pragma once
// The linear spring-dashpot contact of Cundall & Strack (1979) in the form LAMMPS' pair
// gran/hooke/history uses (so the LAMMPS inputs of the same silo mean the same numbers here):
//   normal:     F_n = k_n delta - m_eff gamma_n v_n
//   tangential: F_t = -(k_t s + m_eff gamma_t v_t), |F_t| <= mu |F_n|, s the accumulated
//               tangential displacement (the contact's history).
// With c = m_eff gamma_n, the damping ratio is zeta = c / (2 sqrt(k_n m_eff)) and
// (docs/scenes.md, references) e = exp(-pi zeta / sqrt(1 - zeta^2)), t_c = pi / sqrt(k_n/m_eff - (c/2m_eff)^2).
#include <cmath>

namespace dynweigh::granular {

struct ContactParameters {
  double normal_stiffness = 2.0e4;          // k_n, N/m (peer in.silo2d: 2e4 in LJ units)
  double tangential_stiffness = 2.0e4 * 2.0 / 7.0;  // k_t; LAMMPS' default for NULL is 2/7 k_n
  double normal_damping = 97.0;             // gamma_n, 1/s (peer: 97, e about 0.5)
  double tangential_damping = 97.0 / 2.0;   // gamma_t; LAMMPS' default for NULL is gamma_n / 2
  double friction = 0.5;                    // mu (peer: 0.5)
};

inline double damping_ratio(const ContactParameters& c, double effective_mass) {
  return 0.5 * c.normal_damping * std::sqrt(effective_mass / c.normal_stiffness);
}

inline double restitution_coefficient(const ContactParameters& c, double effective_mass) {
  const double zeta = damping_ratio(c, effective_mass);
  const double pi = std::acos(-1.0);
  return zeta < 1.0 ? std::exp(-pi * zeta / std::sqrt(1.0 - zeta * zeta)) : 0.0;
}

inline double contact_duration(const ContactParameters& c, double effective_mass) {
  const double pi = std::acos(-1.0);
  const double half_gamma = 0.5 * c.normal_damping;
  return pi / std::sqrt(c.normal_stiffness / effective_mass - half_gamma * half_gamma);
}

// Normal damping gamma_n that gives restitution e for a pair of effective mass m_eff.
inline double normal_damping_for_restitution(double e, double normal_stiffness, double effective_mass) {
  const double pi = std::acos(-1.0);
  const double log_e = std::log(e);
  const double zeta = -log_e / std::sqrt(pi * pi + log_e * log_e);
  return 2.0 * zeta * std::sqrt(normal_stiffness / effective_mass);
}

// A stable explicit step: the shortest contact (lightest pair) resolved by `steps_per_contact`
// steps; 25..50 is the usual range (the peer's silo uses about 25).
inline double stable_time_step(const ContactParameters& c, double lightest_effective_mass, double steps_per_contact) {
  return contact_duration(c, lightest_effective_mass) / steps_per_contact;
}

}  // namespace dynweigh::granular
