#include "dynweigh/firmware/learned_valve_timing.hpp"

#include <cmath>

#include "dynweigh/model/bore_area.hpp"
#include "dynweigh/model/gravity.hpp"

namespace dynweigh::firmware {
namespace {
// 2 ms of the valve's jitter and ~2 ms of the estimate's error, with a margin.
template <typename Scalar>
constexpr Scalar kDeadTimeDeadbandS = Scalar(0.006);
// The stroke from the feedback: the time to the end position, less the dead time, is used once it is
// off the datasheet by more than a jiffy of the feedback's resolution and the dead time's error.
template <typename Scalar>
constexpr Scalar kStrokeDeadbandS = Scalar(0.015);
}  // namespace

template <typename Scalar>
void BasicLearnedValveTiming<Scalar>::configure(const ValveDatasheet<Scalar>& datasheet,
                                                const model::BeverlooMaterial<Scalar>& material, Scalar bore_m) {
  const Scalar g = model::kGravity<Scalar>;
  datasheet_ = datasheet;
  measured_dead_s_ = datasheet.dead_s;
  dead_time_doses_ = 0;
  gate_flow_shape_ = model::gate_flow_shape(material, g, bore_m);
  full_closing_ = model::ClosingFlowIntegral<Scalar>(material, g, bore_m);
  half_closing_ = model::ClosingFlowIntegral<Scalar>(material, g, bore_m, Scalar(0.5));
  full_rate_kg_s_ = model::discharge_at_stroke_kg_s(material, g, bore_m, Scalar(1));
  measured_travel_strokes_ = 0;
  travel_timed_ = false;
  use(datasheet.dead_s, datasheet.stroke_s);
}

template <typename Scalar>
void BasicLearnedValveTiming<Scalar>::start_dose() {
  const Scalar dead_s = dead_time_in_use_s();
  use(dead_s, stroke_in_use_s(dead_s));
}

// Called at every dose's open command: the integrals over the stroke were taken by configure().
template <typename Scalar>
void BasicLearnedValveTiming<Scalar>::use(Scalar dead_s, Scalar stroke_s) {
  DoseValveTiming<Scalar>& t = in_use_;
  t.dead_s = dead_s;
  t.stroke_s = stroke_s;
  t.half_flow_ratio = gate_flow_shape_.flow_at(Scalar(0.5));
  t.full_closing_flow_s = full_closing_.seconds(dead_s, stroke_s);
  const Scalar half_rate = full_rate_kg_s_ * t.half_flow_ratio;
  t.half_closing_flow_s =
      half_rate > Scalar(0) ? half_closing_.seconds(dead_s, stroke_s) * full_rate_kg_s_ / half_rate : dead_s;
  t.half_transition_s = dead_s + Scalar(0.25) * stroke_s;
  t.full_closing_duration_s = dead_s + stroke_s;
  t.half_closing_duration_s = dead_s + Scalar(0.5) * stroke_s;
  // Opening mirrors closing: the flow that is missing at the start equals the let-through at the end.
  t.opening_delay_s = dead_s + stroke_s - (t.full_closing_flow_s - dead_s);
  t.ramp_delay_s = std::fmax(Scalar(0), t.opening_delay_s - dead_s);
}

// Each timed first impact joins a running mean of the valve's dead time (the last few doses); it is
// adopted once two doses agree it is off the datasheet by more than the valve's jitter and the
// estimate's error can explain: a valve that has slowed with age, or a datasheet that was wrong.
template <typename Scalar>
void BasicLearnedValveTiming<Scalar>::learn_dead_time(Scalar measured_s) {
  dead_time_doses_ = dead_time_doses_ < kDeadTimeMemory ? dead_time_doses_ + 1 : kDeadTimeMemory;
  measured_dead_s_ += (measured_s - measured_dead_s_) / Scalar(dead_time_doses_);
}

template <typename Scalar>
ValveTimingLearning BasicLearnedValveTiming<Scalar>::learned() const {
  ValveTimingLearning l;
  if (dead_time_doses_ > 0) {
    l.dead_s = float(measured_dead_s_);
    l.dead_doses = std::uint16_t(dead_time_doses_);
  }
  if (measured_travel_strokes_ > 0) {
    l.travel_s = float(measured_travel_s_);
    l.travel_strokes = std::uint16_t(measured_travel_strokes_ < 0xFFFFu ? measured_travel_strokes_ : 0xFFFFu);
  }
  return l;
}

template <typename Scalar>
void BasicLearnedValveTiming<Scalar>::restore(const ValveTimingLearning& learned) {
  if (!sane(learned)) return;
  if (learned.dead_doses > 0) {
    measured_dead_s_ = Scalar(learned.dead_s);
    dead_time_doses_ = learned.dead_doses < kDeadTimeMemory ? learned.dead_doses : kDeadTimeMemory;
  }
  if (learned.travel_strokes > 0 && !travel_timed_) {
    measured_travel_s_ = Scalar(learned.travel_s);
    measured_travel_strokes_ = learned.travel_strokes;
  }
}

template <typename Scalar>
Scalar BasicLearnedValveTiming<Scalar>::dead_time_in_use_s() const {
  const bool clearly_off = std::fabs(measured_dead_s_ - datasheet_.dead_s) > kDeadTimeDeadbandS<Scalar>;
  return dead_time_doses_ >= kDeadTimeMinDoses && clearly_off ? measured_dead_s_ : datasheet_.dead_s;
}

// The stroke as the feedback timed it: the time to the end position less the dead time. Feedback
// that reaches the end position before the valve can have moved (one that echoes the command) times
// nothing.
template <typename Scalar>
Scalar BasicLearnedValveTiming<Scalar>::stroke_in_use_s(Scalar dead_s) const {
  if (measured_travel_strokes_ == 0) return datasheet_.stroke_s;
  const Scalar measured = measured_travel_s_ - dead_s;
  if (!(measured > Scalar(0))) return datasheet_.stroke_s;
  return std::fabs(measured - datasheet_.stroke_s) > kStrokeDeadbandS<Scalar> ? measured : datasheet_.stroke_s;
}

template class BasicLearnedValveTiming<float>;
template class BasicLearnedValveTiming<double>;

}  // namespace dynweigh::firmware
