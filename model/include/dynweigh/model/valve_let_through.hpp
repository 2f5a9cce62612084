#pragma once
// How much flows after the close command: full flow during the dead time, then a falling rate
// while the gate strokes shut. Expressed in seconds of full flow so the caller scales it by the
// flow it measures. Computed once at configuration time, never per jiffy.
#include "dynweigh/model/bore_area.hpp"

namespace dynweigh::model {

template <typename Scalar>
Scalar closing_flow_seconds(const BeverlooMaterial<Scalar>& material, Scalar g,
                            Scalar bore_diameter_m, Scalar dead_time_s, Scalar stroke_time_s,
                            Scalar from_stroke = Scalar(1)) {
  const Scalar full = discharge_at_stroke_kg_s(material, g, bore_diameter_m, Scalar(1));
  if (full <= Scalar(0)) return dead_time_s;
  const Scalar at_start = discharge_at_stroke_kg_s(material, g, bore_diameter_m, from_stroke);
  constexpr int kPanels = 64;  // Simpson's rule; the integrand is smooth but for s -> 0
  const Scalar duration = stroke_time_s * from_stroke;
  Scalar sum = Scalar(0);
  for (int i = 0; i <= kPanels; ++i) {
    const Scalar s = from_stroke * (Scalar(1) - Scalar(i) / Scalar(kPanels));
    const Scalar weight = (i == 0 || i == kPanels) ? Scalar(1) : (i % 2 ? Scalar(4) : Scalar(2));
    sum += weight * discharge_at_stroke_kg_s(material, g, bore_diameter_m, s);
  }
  const Scalar stroking = sum * duration / (Scalar(3) * Scalar(kPanels));
  return (dead_time_s * at_start + stroking) / full;
}

}  // namespace dynweigh::model
