#pragma once
// Beverloo's law for the discharge of a granular bed through a circular orifice:
// W = C rho_b sqrt(g) (D - k d)^(5/2). The rate does not depend on the fill level (Janssen),
// which is why it, not Torricelli, governs a silo. Reference values: docs/physics.md.
#include <cmath>

namespace dynweigh::model {

template <typename Scalar>
struct BeverlooMaterial {
  Scalar coefficient_C = Scalar(0.58);
  Scalar shape_k = Scalar(1.5);
  Scalar grain_diameter_m = Scalar(0.0005);
  Scalar bulk_density = Scalar(1550);
};

template <typename Scalar>
Scalar beverloo_discharge_kg_s(const BeverlooMaterial<Scalar>& material, Scalar g,
                               Scalar orifice_diameter_m) {
  const Scalar free_width = orifice_diameter_m - material.shape_k * material.grain_diameter_m;
  if (free_width <= Scalar(0)) return Scalar(0);  // the orifice arches over: no flow
  return material.coefficient_C * material.bulk_density * std::sqrt(g) *
         free_width * free_width * std::sqrt(free_width);
}

}  // namespace dynweigh::model
