#pragma once
// Height of the heap in a cylindrical container: a cone at the angle of repose until its base
// fills the container, then the cone rises on a growing cylinder. The fall height is measured
// from the orifice to this top.
#include <algorithm>
#include <cmath>

namespace dynweigh::model {

template <typename Scalar>
struct PileGeometry {
  Scalar container_diameter_m = Scalar(0.3);
  Scalar repose_angle_rad = Scalar(32.0 * M_PI / 180.0);
  Scalar bulk_density = Scalar(1550);
};

template <typename Scalar>
Scalar pile_top_height_m(const PileGeometry<Scalar>& pile, Scalar mass_kg) {
  if (mass_kg <= Scalar(0)) return Scalar(0);
  const Scalar volume = mass_kg / pile.bulk_density;
  const Scalar radius = pile.container_diameter_m / Scalar(2);
  const Scalar slope = std::tan(pile.repose_angle_rad);
  const Scalar full_cone_volume = Scalar(M_PI) * radius * radius * radius * slope / Scalar(3);
  if (volume <= full_cone_volume) {
    return slope * std::cbrt(Scalar(3) * volume / (Scalar(M_PI) * slope));
  }
  return radius * slope + (volume - full_cone_volume) / (Scalar(M_PI) * radius * radius);
}

// How fast the top rises per kilogram added: what makes the landing rate exceed the release rate.
template <typename Scalar>
Scalar pile_rise_m_per_kg(const PileGeometry<Scalar>& pile, Scalar mass_kg) {
  const Scalar radius = pile.container_diameter_m / Scalar(2);
  const Scalar slope = std::tan(pile.repose_angle_rad);
  const Scalar height = pile_top_height_m(pile, mass_kg);
  const Scalar cylinder_rise = Scalar(1) / (Scalar(M_PI) * radius * radius * pile.bulk_density);
  if (height >= radius * slope) return cylinder_rise;
  // Cone: H^3 = 3 V tan^2 / pi, so dH/dV = tan^2 / (pi H^2); the apex itself is bounded by the
  // stream's width, taken as a tenth of the container.
  const Scalar h = std::max(height, radius * slope / Scalar(10));
  return std::max(cylinder_rise, slope * slope / (Scalar(M_PI) * h * h * pile.bulk_density));
}

template <typename Scalar>
Scalar fall_height_to_pile_m(const PileGeometry<Scalar>& pile, Scalar orifice_to_floor_m,
                             Scalar mass_kg) {
  constexpr Scalar kMinimumFall = Scalar(0.001);  // the pile has reached the orifice
  return std::max(kMinimumFall, orifice_to_floor_m - pile_top_height_m(pile, mass_kg));
}

}  // namespace dynweigh::model
