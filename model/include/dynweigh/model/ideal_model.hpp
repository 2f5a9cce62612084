#pragma once
// The ideal model of thesis chapter 1 (table 2.1), with the sign of eq. 1.14 corrected
// (docs/physics.md): material leaves the orifice at v0 and falls a height h.
#include <cmath>

namespace dynweigh::model {

template <typename Scalar>
Scalar impact_speed(Scalar v0, Scalar g, Scalar h) {
  return std::sqrt(v0 * v0 + Scalar(2) * g * h);
}

template <typename Scalar>
Scalar fall_time(Scalar v0, Scalar g, Scalar h) {
  return (impact_speed(v0, g, h) - v0) / g;
}

// Thesis eq. 3.16: mdot = alpha v0 A rho.
template <typename Scalar>
Scalar mass_flow(Scalar alpha, Scalar v0, Scalar area, Scalar bulk_density) {
  return alpha * v0 * area * bulk_density;
}

template <typename Scalar>
Scalar outflow_speed(Scalar mass_flow_kg_s, Scalar area, Scalar bulk_density) {
  return mass_flow_kg_s / (area * bulk_density);
}

// Eq. 1.9: the momentum flux of the landing stream.
template <typename Scalar>
Scalar impulse_force(Scalar mass_flow_kg_s, Scalar v0, Scalar g, Scalar h) {
  return mass_flow_kg_s * impact_speed(v0, g, h);
}

// Eq. 1.11: the material between orifice and pile top.
template <typename Scalar>
Scalar mass_in_flight(Scalar mass_flow_kg_s, Scalar v0, Scalar g, Scalar h) {
  return mass_flow_kg_s * fall_time(v0, g, h);
}

// F_dm - F_imp = -mdot v0 (corrected eq. 1.14): closing the valve instantly at constant h, the
// reading at close exceeds the final static weight by mdot v0 / g. Returned as that excess in kg.
template <typename Scalar>
Scalar reading_excess_at_close_kg(Scalar mass_flow_kg_s, Scalar v0, Scalar g) {
  return mass_flow_kg_s * v0 / g;
}

}  // namespace dynweigh::model
