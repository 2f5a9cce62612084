#pragma once
// The final fill if the valve were commanded closed now, by the ideal model of docs/physics.md
// (corrected sign), the pile's rise and the valve's let-through. Before the stream is measured it
// predicts from the prior flow and the valve's timing; once it is, from the estimated static mass
// and landing rate (the observer's, or the line's). A half-open fine feed changes the let-through
// and, until its stream is measured, grows the prediction at the half-open flow.
#include <cmath>
#include <cstdint>

#include "dynweigh/firmware/learned_valve_timing.hpp"
#include "dynweigh/model/beverloo.hpp"
#include "dynweigh/model/final_weight_prediction.hpp"
#include "dynweigh/model/gate_flow_shape.hpp"

namespace dynweigh::firmware {

// What the predictor knows of the plant before the first grain. The defaults are those of the
// parameters named (docs/console.md).
template <typename Scalar>
struct FinalWeightPredictorConfig {
  Scalar jiffy_s = Scalar(0.01);  // s, the control period (`jiffy_ms`, 10 ms)
  Scalar bore_m = Scalar(0.06);   // m, the valve's bore, its full open area (`bore_mm`, 60 mm)
  // The material until it flows: Beverloo's constants for a typical free-flowing sand (C 0.58,
  // k 1.5, grains 0.5 mm) and the bulk density's first guess (`density`, 1550 kg/m^3). The prior
  // flow follows from it and the bore.
  model::BeverlooMaterial<Scalar> material{};
  Scalar orifice_to_floor_m = Scalar(1.2);    // m, orifice to the empty container's bottom (`fall_mm`, 1200 mm)
  Scalar container_diameter_m = Scalar(0.3);  // m (`container_mm`, 300 mm)
  Scalar repose_angle_rad = Scalar(32) * Scalar(M_PI) / Scalar(180);  // rad (`repose_deg`, 32 degrees)
  bool pile_grows = true;  // the heap rises towards the orifice (`pile_rise`, 1); false: the floor's fall height
};

// Scalar is float on the target; the double instantiation is the reference the numerical stress
// tests run beside it.
template <typename Scalar>
class BasicFinalWeightPredictor {
 public:
  void configure(const FinalWeightPredictorConfig<Scalar>& config);
  // The let-through and closing time a close from full open has, until a dose starts.
  void use_valve_timing(const DoseValveTiming<Scalar>& timing);
  // At the open command, with the scale's net grams and the valve's timing for this dose.
  void start(Scalar start_weight_g, const DoseValveTiming<Scalar>& timing);

  // Each returns the fill (grams added by this dose) if the valve were commanded closed now.
  // Before the stream is measured: `jiffies` since the open command at the prior (or fine) flow.
  // A close commanded before the gate has travelled its stroke lets through only what the partial
  // stroke passes (`shape`: how the flow grows along the stroke).
  Scalar from_prior(std::uint32_t jiffies, const model::GateFlowShape<Scalar>& shape) const;
  // How much from_prior() grows in the jiffy after `jiffies`: while the gate is still opening,
  // twice the flow at the stroke it has reached (a later close opens it further and closes it from
  // higher); the prior flow once it is full open.
  Scalar prior_growth_per_jiffy_g(std::uint32_t jiffies, const model::GateFlowShape<Scalar>& shape) const;
  // From the observer: the reading without the ringing, the landing rate now and its mean.
  Scalar from_observer(Scalar equilibrium_g, Scalar rate_g_per_jiffy, Scalar mean_rate_g_per_jiffy);
  // From a line fitted to the unfiltered weight: its value at the newest sample and its slope.
  Scalar from_line(Scalar value_at_newest_g, Scalar slope_g_per_jiffy);

  // The valve goes to half at `jiffies` with `predicted_now_g` predicted for a close from full.
  void switch_to_half(Scalar predicted_now_g, std::uint32_t jiffies);
  bool fine_feeding() const { return fine_; }
  // From the command to half until the half-open stream reaches the pile.
  Scalar half_stream_landing_s() const { return timing_.half_transition_s + last_fall_time_s_; }

  // Grams the fill grows per jiffy at the present flow.
  Scalar growth_per_jiffy_g() const { return growth_per_jiffy_g_; }
  // Seconds from the close command until the last grain has landed.
  Scalar settle_delay_s() const;
  // Orifice to pile top once `net_weight_g` is on the scale.
  Scalar fall_height_m(Scalar net_weight_g) const;
  // The stream's speed at the pile at the last prediction: it sets the impact's share of the reading.
  Scalar impact_speed_m_s() const { return last_impact_speed_m_s_; }
  Scalar prior_rate_kg_s() const { return prior_rate_kg_s_; }
  // The plant with the valve full open.
  model::CutoffGeometry<Scalar> full_open_geometry() const {
    model::CutoffGeometry<Scalar> full = geometry_;
    full.bore_area_m2 = full_area_m2_;
    return full;
  }

 private:
  // The share of its stroke the gate reaches for a close at `open_s`; 1 once it is full open.
  Scalar stroke_reached(Scalar open_s) const;

  model::CutoffGeometry<Scalar> geometry_;  // as the valve stands: full open or half
  Scalar full_area_m2_ = Scalar(0);
  Scalar jiffy_s_ = Scalar(0.01);
  Scalar prior_rate_kg_s_ = Scalar(0);
  DoseValveTiming<Scalar> timing_{};
  Scalar closing_duration_s_ = Scalar(0);

  Scalar start_weight_g_ = Scalar(0);
  Scalar growth_per_jiffy_g_ = Scalar(0);
  Scalar last_fall_time_s_ = Scalar(0);
  Scalar last_fall_height_m_ = Scalar(0);
  Scalar last_impact_speed_m_s_ = Scalar(0);
  bool fine_ = false;
  Scalar predicted_at_switch_g_ = Scalar(0);
  Scalar measured_full_rate_g_per_jiffy_ = Scalar(0);
  std::uint32_t switch_jiffy_ = 0;
};

extern template class BasicFinalWeightPredictor<float>;
extern template class BasicFinalWeightPredictor<double>;

}  // namespace dynweigh::firmware
