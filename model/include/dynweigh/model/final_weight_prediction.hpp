#pragma once
// The final static weight if the valve were told to close now (docs/physics.md).
// The reading holds the static mass plus the momentum flux of the landing stream; the material in
// flight is still to come; together, in the ideal limit, that is the reading minus mdot v0 / g (the
// corrected sign). Beyond the ideal limit: the pile top rises, so material lands faster than it
// leaves the orifice (v / (v + u)), and the valve lets material through while it closes.
#include "dynweigh/model/ideal_model.hpp"
#include "dynweigh/model/pile_geometry.hpp"

namespace dynweigh::model {

template <typename Scalar>
struct CutoffGeometry {
  Scalar g = Scalar(9.81);
  Scalar bore_area_m2 = Scalar(0);
  Scalar bulk_density = Scalar(1550);
  Scalar orifice_to_floor_m = Scalar(1.2);
  PileGeometry<Scalar> pile{};
  bool pile_grows = true;
  Scalar closing_flow_seconds = Scalar(0);  // let-through after the command, in seconds of full flow
};

template <typename Scalar>
struct FinalPrediction {
  Scalar final_kg = 0;
  // final_kg - reading_kg from the small terms alone: at full scale in float the difference of two
  // large numbers would lose the grams a slow flow adds per jiffy.
  Scalar above_reading_kg = 0;
  Scalar static_kg = 0;        // on the scale now
  Scalar in_flight_kg = 0;
  Scalar release_kg_s = 0;     // leaving the orifice
  Scalar outflow_speed_m_s = 0;
  Scalar fall_height_m = 0;
  Scalar fall_time_s = 0;
};

// `reading_kg` is the present reading (or the observer's equilibrium: the reading without the
// ringing) and `reading_rate_kg_s` its slope, which is the landing rate now: it sets the impact's
// share of the reading. `mean_rate_kg_s` is the landing rate over a longer time: the material in
// flight and the valve's let-through leave the orifice after what is landing now, and the silo's
// flow forgets its wandering within a fraction of a fall, so the mean foretells them best.
template <typename Scalar>
FinalPrediction<Scalar> predict_final(const CutoffGeometry<Scalar>& geometry, Scalar reading_kg,
                                      Scalar reading_rate_kg_s, Scalar mean_rate_kg_s) {
  FinalPrediction<Scalar> p;
  const Scalar landing = reading_rate_kg_s > Scalar(0) ? reading_rate_kg_s : Scalar(0);
  const Scalar mean_landing = mean_rate_kg_s > Scalar(0) ? mean_rate_kg_s : Scalar(0);
  p.static_kg = reading_kg;
  p.release_kg_s = mean_landing;
  Scalar impulse_kg = 0;
  // Two fixed-point passes: the static mass sets h, h sets the impulse, the impulse the static mass.
  for (int pass = 0; pass < 2; ++pass) {
    p.fall_height_m = geometry.pile_grows
                          ? fall_height_to_pile_m(geometry.pile, geometry.orifice_to_floor_m, p.static_kg)
                          : geometry.orifice_to_floor_m;
    p.outflow_speed_m_s = outflow_speed(p.release_kg_s, geometry.bore_area_m2, geometry.bulk_density);
    const Scalar v = impact_speed(p.outflow_speed_m_s, geometry.g, p.fall_height_m);
    const Scalar rise = geometry.pile_grows ? pile_rise_m_per_kg(geometry.pile, p.static_kg) * mean_landing
                                            : Scalar(0);
    p.release_kg_s = mean_landing * v / (v + rise);
    impulse_kg = landing * v / geometry.g;
    p.static_kg = reading_kg - impulse_kg;
  }
  p.fall_time_s = fall_time(p.outflow_speed_m_s, geometry.g, p.fall_height_m);
  p.in_flight_kg = p.release_kg_s * p.fall_time_s;
  p.above_reading_kg = p.in_flight_kg + p.release_kg_s * geometry.closing_flow_seconds - impulse_kg;
  p.final_kg = reading_kg + p.above_reading_kg;
  return p;
}

template <typename Scalar>
FinalPrediction<Scalar> predict_final(const CutoffGeometry<Scalar>& geometry, Scalar reading_kg,
                                      Scalar reading_rate_kg_s) {
  return predict_final(geometry, reading_kg, reading_rate_kg_s, reading_rate_kg_s);
}

}  // namespace dynweigh::model
