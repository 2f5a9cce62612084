#pragma once
// How much flows after the close command: full flow during the dead time, then a falling rate
// while the gate strokes shut. Expressed in seconds of full flow so the caller scales it by the
// flow it measures. The integral over the stroke depends only on the material and the bore, so it
// is taken once at configuration time; the dead time and the stroke time, which the valve's
// feedback refines from dose to dose, only scale it (a few operations, fit for the opening jiffy).
#include "dynweigh/model/bore_area.hpp"

namespace dynweigh::model {

template <typename Scalar>
class ClosingFlowIntegral {
 public:
  ClosingFlowIntegral() = default;
  ClosingFlowIntegral(const BeverlooMaterial<Scalar>& material, Scalar g, Scalar bore_diameter_m,
                      Scalar from_stroke = Scalar(1))
      : from_stroke_(from_stroke),
        full_(discharge_at_stroke_kg_s(material, g, bore_diameter_m, Scalar(1))),
        at_start_(discharge_at_stroke_kg_s(material, g, bore_diameter_m, from_stroke)) {
    for (int i = 0; i <= kPanels; ++i) {  // Simpson's rule; the integrand is smooth but for s -> 0
      const Scalar s = from_stroke * (Scalar(1) - Scalar(i) / Scalar(kPanels));
      const Scalar weight = (i == 0 || i == kPanels) ? Scalar(1) : (i % 2 ? Scalar(4) : Scalar(2));
      weighted_rate_sum_ += weight * discharge_at_stroke_kg_s(material, g, bore_diameter_m, s);
    }
  }

  // The let-through of a close that starts `dead_time_s` after its command and strokes shut from
  // `from_stroke` at a pace of `stroke_time_s` for the whole stroke, in seconds of full flow.
  Scalar seconds(Scalar dead_time_s, Scalar stroke_time_s) const {
    if (full_ <= Scalar(0)) return dead_time_s;
    const Scalar duration = stroke_time_s * from_stroke_;
    const Scalar stroking = weighted_rate_sum_ * duration / (Scalar(3) * Scalar(kPanels));
    return (dead_time_s * at_start_ + stroking) / full_;
  }

 private:
  static constexpr int kPanels = 64;
  Scalar from_stroke_ = Scalar(1);
  Scalar full_ = Scalar(0);
  Scalar at_start_ = Scalar(0);
  Scalar weighted_rate_sum_ = Scalar(0);
};

template <typename Scalar>
Scalar closing_flow_seconds(const BeverlooMaterial<Scalar>& material, Scalar g,
                            Scalar bore_diameter_m, Scalar dead_time_s, Scalar stroke_time_s,
                            Scalar from_stroke = Scalar(1)) {
  return ClosingFlowIntegral<Scalar>(material, g, bore_diameter_m, from_stroke).seconds(dead_time_s, stroke_time_s);
}

}  // namespace dynweigh::model
