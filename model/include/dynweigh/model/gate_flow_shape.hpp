#pragma once
// How a slide gate's flow grows along its stroke: Beverloo's rate through the segment of the round
// bore the gate has uncovered (bore_area.hpp), in shares of the full-open flow. A short pulse never
// opens the gate fully: what it lets through is this flow's integral up to the stroke it reached,
// tabulated here once from the configuration (never per jiffy). Near the closed end the slit is
// narrower than the grains' arches and nothing flows; the flow then grows much faster than the
// stroke, so a pulse half as long delivers far less than half.
#include <array>
#include <cstddef>

#include "dynweigh/model/bore_area.hpp"

namespace dynweigh::model {

template <typename Scalar>
struct GateFlowShape {
  static constexpr std::size_t kIntervals = 16;
  // At the stroke i / kIntervals: the flow, and its integral over the stroke from closed.
  std::array<Scalar, kIntervals + 1> flow{};
  std::array<Scalar, kIntervals + 1> integral{};

  // A flow in proportion to the stroke: the shape when the bore lets nothing through at all.
  static GateFlowShape proportional() {
    GateFlowShape shape;
    for (std::size_t i = 0; i <= kIntervals; ++i) {
      const Scalar x = Scalar(i) / Scalar(kIntervals);
      shape.flow[i] = x;
      shape.integral[i] = x * x / Scalar(2);
    }
    return shape;
  }

  Scalar flow_at(Scalar stroke) const { return interpolate(flow, stroke); }
  Scalar integral_to(Scalar stroke) const { return interpolate(integral, stroke); }
  // A gate commanded closed before it reached its end goes on opening for the dead time, to
  // `reached` of its stroke, and closes from there as fast: what passes, in seconds of the full-open
  // flow, for a gate that takes `full_stroke_s` to travel the whole stroke.
  Scalar ramps_seconds(Scalar reached, Scalar full_stroke_s) const {
    return Scalar(2) * full_stroke_s * integral_to(reached);
  }

  // The stroke up to which the flow's integral is `value` (the integral rises with the stroke).
  Scalar stroke_for_integral(Scalar value) const {
    if (value <= integral[0]) return Scalar(0);
    for (std::size_t i = 1; i <= kIntervals; ++i) {
      if (value <= integral[i]) {
        const Scalar rise = integral[i] - integral[i - 1];
        const Scalar share = rise > Scalar(0) ? (value - integral[i - 1]) / rise : Scalar(1);
        return (Scalar(i - 1) + share) / Scalar(kIntervals);
      }
    }
    return Scalar(1);
  }

 private:
  static Scalar interpolate(const std::array<Scalar, kIntervals + 1>& table, Scalar stroke) {
    const Scalar at = (stroke < Scalar(0) ? Scalar(0) : (stroke > Scalar(1) ? Scalar(1) : stroke)) *
                      Scalar(kIntervals);
    const std::size_t i = at >= Scalar(kIntervals) ? kIntervals - 1 : std::size_t(at);
    const Scalar share = at - Scalar(i);
    return table[i] + share * (table[i + 1] - table[i]);
  }
};

// The shape of `material` through a round bore behind a slide gate: Simpson's rule on each interval.
template <typename Scalar>
GateFlowShape<Scalar> gate_flow_shape(const BeverlooMaterial<Scalar>& material, Scalar g, Scalar bore_diameter_m) {
  constexpr std::size_t n = GateFlowShape<Scalar>::kIntervals;
  const Scalar full = discharge_at_stroke_kg_s(material, g, bore_diameter_m, Scalar(1));
  if (!(full > Scalar(0))) return GateFlowShape<Scalar>::proportional();
  const auto share_at = [&](Scalar stroke) {
    return discharge_at_stroke_kg_s(material, g, bore_diameter_m, stroke) / full;
  };
  GateFlowShape<Scalar> shape;
  const Scalar h = Scalar(1) / Scalar(n);
  shape.flow[0] = share_at(Scalar(0));
  for (std::size_t i = 1; i <= n; ++i) {
    const Scalar x = Scalar(i) * h;
    shape.flow[i] = share_at(x);
    const Scalar middle = share_at(x - h / Scalar(2));
    shape.integral[i] = shape.integral[i - 1] + h / Scalar(6) * (shape.flow[i - 1] + Scalar(4) * middle + shape.flow[i]);
  }
  return shape;
}

}  // namespace dynweigh::model
