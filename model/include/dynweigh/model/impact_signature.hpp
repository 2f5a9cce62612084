#pragma once
// What the first seconds of a dose say about the material (thesis: the first impulse and the flow
// rate reveal it). Once the ringing is removed the reading is the static mass plus the stream's
// momentum flux, W = m_static + mdot v / g. The static mass is the landing rate times the time
// since the landing effectively began, so the rest of W is the impulse, and the impulse over the
// rate is the impact speed. With the outflow speed from the rate and the bore, the speed gained in
// the fall says how far the grains fell.
#include <cmath>

#include "dynweigh/model/ideal_model.hpp"

namespace dynweigh::model {

template <typename Scalar>
struct ImpactObservation {
  Scalar equilibrium_g = 0;      // W above the empty reading, ringing removed
  Scalar since_open_s = 0;       // when W holds, from the open command
  Scalar landing_rate_kg_s = 0;  // mdot, the slope of W
  // Where the landed mass extrapolates to zero: the first impact plus the lag the flow's ramp
  // during the stroke leaves behind it (landing_start_s below).
  Scalar landing_start_s = 0;
};

// The first impact comes with the first grains; a linear extrapolation of the landed mass starts
// later by the seconds the rate took to ramp up (half the ramp, for a linear one).
template <typename Scalar>
Scalar landing_start_s(Scalar first_impact_s, Scalar ramp_delay_s) {
  return first_impact_s + ramp_delay_s;
}

template <typename Scalar>
struct ImpactSignature {
  bool valid = false;               // a flow, a positive impulse, and a stream that sped up
  Scalar static_kg = 0;
  Scalar impulse_kg = 0;            // mdot v / g
  Scalar impact_speed_m_s = 0;      // v
  Scalar outflow_speed_m_s = 0;     // v0 = mdot / (rho A)
  Scalar implied_fall_height_m = 0; // (v^2 - v0^2) / (2 g)
};

// The landing rate stands in for the outflow: they differ by the pile's rise speed over the
// impact speed (final_weight_prediction.hpp), a fraction of a percent early in a dose.
template <typename Scalar>
ImpactSignature<Scalar> impact_signature(const ImpactObservation<Scalar>& seen, Scalar bore_area_m2,
                                         Scalar bulk_density, Scalar g) {
  ImpactSignature<Scalar> s;
  const Scalar mdot = seen.landing_rate_kg_s;
  if (!(mdot > Scalar(0)) || !(bore_area_m2 > Scalar(0)) || !(bulk_density > Scalar(0))) return s;
  const Scalar landed_for_s = seen.since_open_s - seen.landing_start_s;
  s.static_kg = mdot * (landed_for_s > Scalar(0) ? landed_for_s : Scalar(0));
  s.impulse_kg = seen.equilibrium_g / Scalar(1000) - s.static_kg;
  s.impact_speed_m_s = g * s.impulse_kg / mdot;
  s.outflow_speed_m_s = outflow_speed(mdot, bore_area_m2, bulk_density);
  s.implied_fall_height_m = (s.impact_speed_m_s * s.impact_speed_m_s - s.outflow_speed_m_s * s.outflow_speed_m_s) /
                            (Scalar(2) * g);
  s.valid = s.impulse_kg > Scalar(0) && s.impact_speed_m_s >= s.outflow_speed_m_s && std::isfinite(s.impact_speed_m_s);
  return s;
}

}  // namespace dynweigh::model
