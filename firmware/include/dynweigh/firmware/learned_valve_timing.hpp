#pragma once
// The valve as the model strategy times it: what it lets through while it closes (from full and
// from half open), how long it takes to shut, and the flow missing while it opens. From the
// datasheet's dead time and stroke, or from what the scale has measured of them: the dead time from
// the doses' first impacts, the stroke from the valve's feedback (valve_timing.hpp). What is learned
// is adopted when a dose starts, never within one.
#include <cstdint>

#include "dynweigh/firmware/valve_timing_learning.hpp"
#include "dynweigh/model/beverloo.hpp"
#include "dynweigh/model/gate_flow_shape.hpp"
#include "dynweigh/model/valve_let_through.hpp"

namespace dynweigh::firmware {

// The valve as its datasheet gives it (the `valve_dead_ms` and `valve_stroke_ms` parameters).
template <typename Scalar>
struct ValveDatasheet {
  Scalar dead_s = Scalar(0.03);    // s, from the command to the first motion; default 30 ms
  Scalar stroke_s = Scalar(0.08);  // s, a full stroke once moving; default 80 ms
};

// One dose's valve timing, fixed when the valve is commanded open.
template <typename Scalar>
struct DoseValveTiming {
  Scalar dead_s = Scalar(0);
  Scalar stroke_s = Scalar(0);
  Scalar half_flow_ratio = Scalar(0.5);       // Beverloo: half-open flow / full flow
  Scalar full_closing_flow_s = Scalar(0);     // let-through closing from full open, in seconds of full flow
  Scalar half_closing_flow_s = Scalar(0);     // closing from half open, in seconds of half-open flow
  Scalar half_transition_s = Scalar(0);       // from the command to half until the flow is half
  Scalar full_closing_duration_s = Scalar(0);  // from the close command until shut: dead time and stroke
  Scalar half_closing_duration_s = Scalar(0);  // the same from half open
  Scalar opening_delay_s = Scalar(0);         // the flow missing at the opening, in seconds of full flow
  Scalar ramp_delay_s = Scalar(0);            // the landed mass's line starts this long after the first grain
};

template <typename Scalar>
class BasicLearnedValveTiming {
 public:
  // The dead time learned from the first impacts: a running mean over this many doses, used from
  // the second dose on when it is off the datasheet by more than the deadband.
  static constexpr std::uint32_t kDeadTimeMemory = 8;
  static constexpr std::uint32_t kDeadTimeMinDoses = 2;

  // `material` and the bore set the flow the let-through is counted in. Forgets what was learned.
  void configure(const ValveDatasheet<Scalar>& datasheet, const model::BeverlooMaterial<Scalar>& material,
                 Scalar bore_m);
  // A dose whose stream ran measurably timed its first impact: one more measured dead time.
  void learn_dead_time(Scalar measured_s);
  // What the valve's feedback showed: the mean time from the command to the end position over
  // `strokes` full strokes. No stroke timed (a restart): what was restored stands.
  void measured_travel(Scalar mean_s, std::uint32_t strokes) {
    if (strokes == 0) return;
    measured_travel_s_ = mean_s;
    measured_travel_strokes_ = strokes;
    travel_timed_ = true;
  }
  // What has been measured, to keep with the material dosed.
  ValveTimingLearning learned() const;
  // What earlier doses of a material measured (checked by sane()). A material with nothing measured
  // keeps what the valve has shown so far: the valve is the same whatever flows through it. The
  // travel the feedback timed since the start is newer than any stored one, and stands.
  void restore(const ValveTimingLearning& learned);
  // At the open command: the timing of the dose that begins, from what has been learned so far.
  void start_dose();
  const DoseValveTiming<Scalar>& in_use() const { return in_use_; }
  // The stroke the feedback's timing gives for a dead time of `dead_s` (the datasheet's, where it
  // timed none or one within the deadband of it).
  Scalar stroke_in_use_s(Scalar dead_s) const;
  // How the flow grows along the stroke (its value at half stroke is the half-open flow's share),
  // for pulses too short to open the gate fully.
  const model::GateFlowShape<Scalar>& gate_flow_shape() const { return gate_flow_shape_; }

 private:
  void use(Scalar dead_s, Scalar stroke_s);
  Scalar dead_time_in_use_s() const;

  model::GateFlowShape<Scalar> gate_flow_shape_ = model::GateFlowShape<Scalar>::proportional();
  model::ClosingFlowIntegral<Scalar> full_closing_{};  // from the open gate
  model::ClosingFlowIntegral<Scalar> half_closing_{};  // from half stroke
  Scalar full_rate_kg_s_ = Scalar(0);
  ValveDatasheet<Scalar> datasheet_{};
  Scalar measured_dead_s_ = Scalar(0);  // running mean over the last doses' first impacts
  std::uint32_t dead_time_doses_ = 0;
  Scalar measured_travel_s_ = Scalar(0);
  std::uint32_t measured_travel_strokes_ = 0;
  bool travel_timed_ = false;  // by the feedback since configure(), not restored
  DoseValveTiming<Scalar> in_use_{};
};

extern template class BasicLearnedValveTiming<float>;
extern template class BasicLearnedValveTiming<double>;

}  // namespace dynweigh::firmware
