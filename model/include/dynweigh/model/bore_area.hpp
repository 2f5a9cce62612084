#pragma once
// Open area of a round bore uncovered by a slide gate: the gate's straight edge has travelled
// a fraction s of the diameter, leaving a circular segment open. Area is not linear in s, and
// Beverloo's rate is not linear in area: both matter for the let-through while the valve moves.
#include <algorithm>
#include <cmath>

#include "dynweigh/model/beverloo.hpp"

namespace dynweigh::model {

template <typename Scalar>
Scalar bore_area_m2(Scalar bore_diameter_m) {
  return Scalar(M_PI) / Scalar(4) * bore_diameter_m * bore_diameter_m;
}

// Fraction of the bore's area open at stroke s in [0, 1].
template <typename Scalar>
Scalar open_area_fraction(Scalar stroke) {
  const Scalar s = std::clamp(stroke, Scalar(0), Scalar(1));
  // Circular segment of height s*D in a circle of radius 1/2, normalised by the circle's area.
  const Scalar c = Scalar(1) - Scalar(2) * s;  // cos of the half angle
  const Scalar half_angle = std::acos(c);
  return (half_angle - c * std::sqrt(std::max(Scalar(0), Scalar(1) - c * c))) / Scalar(M_PI);
}

// Diameter of the circle with the same open area: what Beverloo's law sees.
template <typename Scalar>
Scalar equivalent_diameter_m(Scalar bore_diameter_m, Scalar stroke) {
  return bore_diameter_m * std::sqrt(open_area_fraction(stroke));
}

template <typename Scalar>
Scalar discharge_at_stroke_kg_s(const BeverlooMaterial<Scalar>& material, Scalar g,
                                Scalar bore_diameter_m, Scalar stroke) {
  return beverloo_discharge_kg_s(material, g, equivalent_diameter_m(bore_diameter_m, stroke));
}

}  // namespace dynweigh::model
