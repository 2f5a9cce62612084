#pragma once
// How long a top-up pulse opens the valve for the mass still missing. The valve reaches its
// position `travel` after the dead time and closes at the same speed; the dead time shifts the
// opening and the closing alike. A pulse of T seconds that reaches the position lets through about
// q (T - travel) plus what flows while the gate moves; one that does not reach it lets through what
// flows while the gate opens to T / travel of the way and closes again, which is far less than the
// time suggests: the flow grows with the stroke much faster than in proportion (the shape from the
// bore and Beverloo, model/gate_flow_shape.hpp). The flow's start-up and a valve slower than its
// datasheet take more off each pulse. The law is m = q e(T) - c, e(T) the pulse's mass in seconds of
// the flow at its position, one law for full-open pulses and one for half-open ones. q starts from the
// flow the dose measured, c from zero; the dose itself (one long full-open pulse) and each pulse's
// measured mass refine them (recursive least squares), so each pulse is sized from what the last did.
// What pulses taught is this valve's and this material's answer to a short opening, whatever the
// target: it is kept with the material (top_up_pulse_learning.hpp) and the next dose's pulses start
// from it instead of from the dose, whose long opening's start-up loss is no short pulse's. A
// pulse's mass weighs as much as the last ten's (forgetting), so the law follows a silo running low.
// A pulse shorter than the valve's travel opens the gate only part of the way, so what it lets
// through depends on how fast the gate moves, and the datasheet's stroke is often far off (a valve
// whose feedback never saw a full stroke, on a plant whose doses all close before the valve is
// open). Each pulse that may not have opened fully also teaches the travel: once q and c have
// learned from the pulse, the travel under which they would have predicted what it delivered,
// taken a share of the way (within a quarter and four times the stroke in use: the datasheet's, or
// the one the feedback timed). A valve whose feedback shows the half position has its half strokes
// timed (valve_timing.hpp): from the pulse after the first that reached half, the half-open law
// travels as the feedback showed, which no pulse's mass tells as well (a new material's first dose,
// on a valve two or three times slower than its datasheet, sized its short last pulse for a gate
// that opened far further than it did). Each dose's first pulse and each stroke timed since set it
// afresh; between, the pulses' masses refine it as above.
// A pulse aims short of the deficit: the first (and any of a law no pulse has taught, only the dose's
// long opening) by a fixed share, the later ones by twice what the
// law is still unsure of plus the valve's timing jitter (an overfill cannot be undone). The last
// pulse a dose may give aims at the whole deficit less half of what the law is still unsure of, but
// not short by the jitter as the others are: every fill that needs it would end short by that, a bias
// no later pulse corrects. A law that pulses like this one have taught holds back little; one taught
// by a pulse or two of another length (a new material's first dose) holds back more. A law only the
// dose taught aims its last pulse at the whole deficit. The pulse before the last aims where the fill is likeliest
// to end within its class (pulse_pair_risk.hpp): the sure aim would leave the last pulse a large
// share of the deficit, and that pulse's scatter with it (a new material's first dose spends all its
// pulses; a small pulse on a fast valve scatters by its jitter times the flow, whatever its size).
// Of aims about as likely, it takes the one that more often finishes the fill itself, without
// leaving the fill above the target by more than the class allows the fills' mean: each chance a
// weight (kAnotherPulseWorth, kAboveMeanLimitWorth) beside the miss chance. Aiming for the class
// alone, it aimed at 0.8 of 72 g where the cycle tops up below 16 g, and the last pulse followed
// more often than not (docs/plant-family.md, The pulse before the last weighs its time).
// The pulses open the valve half, unless even the longest pulse allowed could not bring the deficit
// at half open's flow. A pulse's mass is off by the valve's timing jitter times the flow where the
// gate turns back (the jitter moves both the turn and the closing ramp that follows it). A
// full-open pulse of a few hundred grams turns part-way up the stroke, where the flow is already
// more than half open's, or at full flow; a half-open one never turns above half open's flow.
#include <cstdint>

#include "dynweigh/firmware/io.hpp"
#include "dynweigh/firmware/top_up_pulse_learning.hpp"
#include "dynweigh/firmware/two_parameter_rls.hpp"
#include "dynweigh/model/gate_flow_shape.hpp"

namespace dynweigh::firmware {

class TopUpPulseLaw {
 public:
  struct Pulse {
    ValveCommand command = ValveCommand::open;
    float seconds = 0.0f;
    float expected_g = 0.0f;
  };
  static constexpr float kFirstAim = 0.8f;    // share of the deficit, before any pulse was seen
  static constexpr float kLaterAim = 0.9f;    // at most, once the law has seen one
  static constexpr float kLeastAim = 0.6f;    // at least, however unsure the law
  static constexpr float kJitterS = 0.005f;   // the valve's timing jitter a pulse must allow for
  // A pulse this long is no short pulse: the flow's start-up (up to half a second) has settled in
  // it, and a law taught on short pulses, whose flow was still starting, expects too little of it.
  // Unless it is the dose's last, it aims at kLeastAim of the deficit.
  static constexpr float kLongPulseS = 0.4f;
  static constexpr int kRiskAimSteps = 4;      // aims tried, from kLeastAim to the whole deficit
  // What the pulse before the last weighs beside its miss chance, in chances of missing the class:
  // that the last pulse must still follow (a second landing and certification, 0.5 to 1.2 s on the
  // plant family), and that the fill ends above the target by more than the class allows the mean.
  // On the plant families (docs/plant-family.md) weights of 0.003 to 0.02 and 0.01 to 0.06 all left
  // about 2 % more cells unbeaten by every baseline; the second weight is what keeps the steady
  // share: without it the fills that finish end above the target on average (the short ones are
  // topped up, the long ones stay).
  static constexpr float kAnotherPulseWorth = 0.005f;
  static constexpr float kAboveMeanLimitWorth = 0.03f;
  // What may follow a pulse: how many more pulses the dose allows, the limit of the class its fill
  // must end within (0: none given, the sure aim), how far short the cycle accepts a fill without
  // another pulse, and how far above the target the class allows the fills' mean (0: neither
  // weighed, the aim for the class alone).
  struct Outlook {
    std::uint8_t pulses_after = 255;
    float limit_g = 0.0f;
    float accepted_short_g = 0.0f;
    float mean_limit_g = 0.0f;
  };

  // A dose's full-open flow (grams per second), the share of it half open lets through, the
  // valve's stroke (closed to full open), the longest pulse allowed, and how the flow grows along the
  // stroke. A law pulses taught (in this dose, or earlier ones: restore()) is kept.
  void begin(float full_flow_g_s, float half_flow_ratio, float stroke_s, float max_pulse_s,
             const model::GateFlowShape<float>& shape = model::GateFlowShape<float>::proportional());
  // The dose as one long full-open pulse: `open_s` from the open command to the close,
  // `delivered_g` certified. The full-open law's first observation, unless pulses taught it.
  void observe_dose(float open_s, float delivered_g);
  // Before a dose: what this material's pulses taught (nothing: the next begin starts afresh).
  void restore(const TopUpPulseLearning& learned);
  TopUpPulseLearning learned() const;
  // The pulse for `deficit_g` still missing; the first chooses full or half open for them all.
  // `last`: the dose gives no pulse after this one.
  Pulse size(float deficit_g, bool last = false);
  Pulse size(float deficit_g, const Outlook& outlook);
  // What the pulse just given delivered, as the scale certified it.
  void learn(const Pulse& pulse, float delivered_g);
  // The valve's feedback timed the gate's travel to the full (`half` false) or half position: the
  // law's travel, and the bounds its pulses may teach within, unless the law took this timing already.
  void timed_travel(bool half, float travel_s);
  // The law of full-open (`half` false) or half-open pulses.
  float flow_g_s(bool half) const { return law(half).rls.state().theta1; }
  float start_loss_g(bool half) const { return law(half).rls.state().theta2; }
  std::uint8_t pulses_seen(bool half) const { return law(half).seen; }
  float travel_s(bool half) const { return law(half).travel_s; }
  float expected_g(bool half, float seconds) const;

 private:
  struct Law {
    TwoParameterRls rls;
    float prior_flow_g_s = 0.0f;
    float travel_s = 0.0f;        // to the law's position: learned from pulses (learn_travel)
    float prior_travel_s = 0.0f;  // the datasheet's or the feedback's: the learned one's bounds
    float end_stroke = 1.0f;  // the gate's position: full or half open
    std::uint8_t seen = 0;
    std::uint8_t pulses = 0;  // of `seen`, the pulses (not the dose)
  };
  const Law& law(bool half) const { return half ? half_ : full_; }
  Law& law(bool half) { return half ? half_ : full_; }
  static void reset(Law& law, float flow_g_s, float travel_s);
  float ramps_s(const Law& law, float stroke) const;
  static bool restore(Law& law, const PulseLawLearning& learned);
  static PulseLawLearning learned(const Law& law);
  void observe(Law& law, float seconds, float delivered_g);
  float predicted_g(const Law& law, float seconds) const;
  float travel_explaining(const Law& law, float seconds, float delivered_g) const;
  void learn_travel(Law& law, float seconds, float delivered_g);
  float open_seconds(const Law& law, float pulse_s) const;
  float pulse_seconds(const Law& law, float open_s) const;
  float seconds_for(const Law& law, float mass_g) const;
  float unsure_g(const Law& law, float seconds) const;
  float spread_g(const Law& law, float seconds) const;
  float aim_g(const Law& law, float deficit_g, const Outlook& outlook) const;
  float sure_aim_g(const Law& law, float deficit_g) const;
  float risk_aim_g(const Law& law, float deficit_g, const Outlook& outlook) const;
  void choose(float deficit_g);

  Law full_;
  Law half_;
  model::GateFlowShape<float> shape_ = model::GateFlowShape<float>::proportional();
  float max_pulse_s_ = 1.0f;
  bool chosen_ = false;
  bool half_open_ = false;
};

}  // namespace dynweigh::firmware
