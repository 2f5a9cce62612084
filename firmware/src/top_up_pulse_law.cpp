#include "dynweigh/firmware/top_up_pulse_law.hpp"

#include <cmath>

#include "dynweigh/firmware/pulse_pair_risk.hpp"

namespace dynweigh::firmware {
namespace {
// A learned flow is held within these shares of its prior: a pulse whose mass was read badly must
// not make the next one absurd.
constexpr float kFlowLow = 0.25f;
constexpr float kFlowHigh = 2.0f;
// The prior: the flow within half of the measured one; the loss (the flow's start-up, a valve
// slower than its datasheet) 30 +- 30 ms of flow, at most 200 ms.
constexpr float kFlowSpread = 0.5f;
constexpr float kLossPriorS = 0.03f;
constexpr float kLossSpreadS = 0.03f;
constexpr float kLossMaxS = 0.2f;
constexpr float kPulseNoiseG = 1.0f;
constexpr float kShortestPulseS = 0.001f;
constexpr float kAimSigmas = 2.0f;
// The last pulse holds back half of what the law is unsure of (not the jitter: that every pulse has),
// once pulses taught it: a law only the dose taught knows no pulse, and the fill would end short.
constexpr float kLastAimSigmas = 0.5f;
// A pulse's lesson weighs as much as the last ten's: the law follows the silo's level and the valve.
constexpr float kForgetting = 0.9f;
// No valve takes 10 s to travel: a stored law that says so is no law.
constexpr float kLongestTravelS = 10.0f;
// The loss builds up over the flow's start-up: a pulse open for less than this loses in proportion.
constexpr float kLossBuildS = 0.1f;

// The travel a pulse may teach: between these shares of the stroke in use (the datasheet's, or the
// one the valve's feedback timed). A pulse moves the learned one a share of the way to what it
// showed (its mass is uncertain by the flow's fluctuation and the valve's jitter), in one step at
// most by this factor.
constexpr float kTravelLow = 0.25f;
constexpr float kTravelHigh = 4.0f;
constexpr float kTravelGain = 0.3f;
constexpr float kTravelStepFactor = 2.0f;
constexpr int kTravelBisections = 10;
constexpr float kRelearnTravelFactor = 2.0f;

float held(float value, float low, float high) { return value < low ? low : (value > high ? high : value); }

float loss_regressor(float open_s) { return open_s < kLossBuildS ? -open_s / kLossBuildS : -1.0f; }
}  // namespace

void TopUpPulseLaw::reset(Law& law, float flow_g_s, float travel_s) {
  law.prior_flow_g_s = flow_g_s;
  law.travel_s = travel_s;
  law.seen = 0;
  // One pulse's mass is uncertain by the valve's jitter at this flow, and read to about a gram.
  const float jitter_g = kJitterS * flow_g_s;
  law.rls.configure(kForgetting, jitter_g > kPulseNoiseG ? jitter_g : kPulseNoiseG);
  law.rls.reset(flow_g_s, kLossPriorS * flow_g_s, kFlowSpread * flow_g_s, kLossSpreadS * flow_g_s);
}

void TopUpPulseLaw::begin(float full_flow_g_s, float half_flow_ratio, float stroke_s, float max_pulse_s,
                          const model::GateFlowShape<float>& shape) {
  const float flow = full_flow_g_s > 0.0f ? full_flow_g_s : 0.0f;
  const float ratio = half_flow_ratio > 0.0f && half_flow_ratio <= 1.0f ? half_flow_ratio : 0.5f;
  const float stroke = stroke_s > 0.0f ? stroke_s : 0.0f;
  max_pulse_s_ = max_pulse_s;
  shape_ = shape;
  full_.end_stroke = 1.0f;
  half_.end_stroke = 0.5f;
  full_.prior_travel_s = stroke;
  half_.prior_travel_s = 0.5f * stroke;
  chosen_ = false;
  if (full_.pulses == 0) reset(full_, flow, stroke);
  if (half_.pulses == 0) reset(half_, flow * ratio, 0.5f * stroke);
}

// What flows while the gate opens to `stroke` and closes again, in seconds of the flow at the law's
// position.
float TopUpPulseLaw::ramps_s(const Law& law, float stroke) const {
  return shape_.ramps_seconds(stroke, law.travel_s / law.end_stroke) / shape_.flow_at(law.end_stroke);
}

float TopUpPulseLaw::open_seconds(const Law& law, float pulse_s) const {
  if (law.travel_s <= 0.0f || !(shape_.flow_at(law.end_stroke) > 0.0f)) return pulse_s;
  if (pulse_s >= law.travel_s) return pulse_s - law.travel_s + ramps_s(law, law.end_stroke);
  return ramps_s(law, law.end_stroke * pulse_s / law.travel_s);
}

// open_seconds() inverted.
float TopUpPulseLaw::pulse_seconds(const Law& law, float open_s) const {
  const float end_flow = shape_.flow_at(law.end_stroke);
  if (law.travel_s <= 0.0f || !(end_flow > 0.0f)) return open_s;
  const float ramps = ramps_s(law, law.end_stroke);
  if (open_s >= ramps) return open_s - ramps + law.travel_s;
  const float full_stroke_s = law.travel_s / law.end_stroke;
  return full_stroke_s * shape_.stroke_for_integral(open_s * end_flow / (2.0f * full_stroke_s));
}

void TopUpPulseLaw::observe(Law& law, float seconds, float delivered_g) {
  const float open_s = open_seconds(law, seconds);
  if (!law.rls.update(open_s, loss_regressor(open_s), delivered_g)) return;
  TwoParameterRls::State s = law.rls.state();
  // A loss or a flow beyond its bounds is held at the bound, and the other moves with it as far as
  // the law's covariance ties the two: the fit of the law given the held value. Holding one alone
  // would keep the other where the unbounded fit put it: a pulse that brought more than expected,
  // explained by a loss below zero, would have lowered the flow, the next pulse longer, the miss
  // larger.
  const float c_low = 0.0f, c_high = kLossMaxS * law.prior_flow_g_s;
  const float c_held = held(s.theta2, c_low, c_high);
  if (c_held != s.theta2 && s.p22 > 0.0f) s.theta1 += s.p12 / s.p22 * (c_held - s.theta2);
  s.theta2 = c_held;
  const float q_held = held(s.theta1, kFlowLow * law.prior_flow_g_s, kFlowHigh * law.prior_flow_g_s);
  if (q_held != s.theta1 && s.p11 > 0.0f) {
    s.theta2 = held(s.theta2 + s.p12 / s.p11 * (q_held - s.theta1), c_low, c_high);
  }
  s.theta1 = q_held;
  law.rls.restore(s);
  if (law.seen < 255) ++law.seen;
}

bool TopUpPulseLaw::restore(Law& law, const PulseLawLearning& learned) {
  const TwoParameterRls::State& l = learned.law;
  const bool sane = learned.pulses > 0 && learned.prior_flow_g_s > 0.0f && std::isfinite(learned.prior_flow_g_s) &&
                    learned.travel_s >= 0.0f && learned.travel_s < kLongestTravelS &&
                    l.theta1 >= kFlowLow * learned.prior_flow_g_s && l.theta1 <= kFlowHigh * learned.prior_flow_g_s &&
                    l.theta2 >= 0.0f && l.theta2 <= kLossMaxS * learned.prior_flow_g_s;
  if (!sane) return false;
  reset(law, learned.prior_flow_g_s, learned.travel_s);
  if (!law.rls.restore(l)) return false;
  law.seen = law.pulses = learned.pulses;
  return true;
}

// Each law on its own: one that no pulse taught (or not sanely) starts from the next dose's flow.
void TopUpPulseLaw::restore(const TopUpPulseLearning& learned) {
  if (!restore(full_, learned.full)) full_ = Law{};
  if (!restore(half_, learned.half)) half_ = Law{};
}

PulseLawLearning TopUpPulseLaw::learned(const Law& law) {
  PulseLawLearning l;
  if (law.pulses == 0) return l;
  l.law = law.rls.state();
  l.prior_flow_g_s = law.prior_flow_g_s;
  l.travel_s = law.travel_s;
  l.pulses = law.pulses;
  return l;
}

TopUpPulseLearning TopUpPulseLaw::learned() const { return {learned(full_), learned(half_)}; }

void TopUpPulseLaw::observe_dose(float open_s, float delivered_g) {
  if (full_.pulses > 0) return;
  if (open_s > 0.0f && delivered_g > 0.0f) observe(full_, open_s, delivered_g);
  // What the dose taught of the flow carries to half open in proportion.
  if (full_.prior_flow_g_s > 0.0f && half_.seen == 0) {
    const float share = full_.rls.state().theta1 / full_.prior_flow_g_s;
    reset(half_, half_.prior_flow_g_s * share, half_.travel_s);
  }
}

float TopUpPulseLaw::predicted_g(const Law& law, float seconds) const {
  const float open_s = open_seconds(law, seconds);
  return law.rls.predict(open_s, loss_regressor(open_s));
}

// The travel under which the law predicts `delivered_g` for this pulse, within the bounds. A
// slower gate opens less in the same pulse, so the prediction falls as the travel grows: bisection.
float TopUpPulseLaw::travel_explaining(const Law& law, float seconds, float delivered_g) const {
  Law trial = law;
  float slow = kTravelHigh * law.prior_travel_s, fast = kTravelLow * law.prior_travel_s;
  trial.travel_s = slow;
  if (predicted_g(trial, seconds) >= delivered_g) return slow;
  trial.travel_s = fast;
  if (predicted_g(trial, seconds) <= delivered_g) return fast;
  for (int i = 0; i < kTravelBisections; ++i) {
    trial.travel_s = std::sqrt(slow * fast);
    (predicted_g(trial, seconds) > delivered_g ? fast : slow) = trial.travel_s;
  }
  return std::sqrt(slow * fast);
}

// Only a pulse that may have stopped short of the position teaches the travel: one shorter than the
// travel learned so far, or one that delivered less than expected and is shorter than the slowest
// travel allowed. A longer one hardly depends on it.
void TopUpPulseLaw::learn_travel(Law& law, float seconds, float delivered_g) {
  if (!(law.prior_travel_s > 0.0f) || !(law.travel_s > 0.0f) || !(delivered_g >= 0.0f)) return;
  const bool short_of_travel = seconds < law.travel_s;
  const bool less_than_expected = delivered_g < predicted_g(law, seconds) && seconds < kTravelHigh * law.prior_travel_s;
  if (!short_of_travel && !less_than_expected) return;
  const float ratio = travel_explaining(law, seconds, delivered_g) / law.travel_s;
  const float step = std::pow(ratio, kTravelGain);
  law.travel_s *= step > kTravelStepFactor ? kTravelStepFactor : (step < 1.0f / kTravelStepFactor ? 1.0f / kTravelStepFactor : step);
}

// A timing the law has not taken yet (a dose's first pulse, whose begin() set the stroke's share as
// the prior, or a stroke timed since) replaces its travel; between two, the pulses' masses refine it
// (learn_travel), as they do a travel no feedback timed. What pulses taught of the flow and the loss
// under a travel off by more than kRelearnTravelFactor is as unsure again as the prior: the valve's
// first pulse, sized and taught with the datasheet's 80 ms where the gate took 300, made the law's
// flow low, short pulses then agreed with it, and a long one overfilled.
void TopUpPulseLaw::timed_travel(bool half, float travel_s) {
  if (!(travel_s > 0.0f) || !(travel_s < kLongestTravelS)) return;
  Law& l = law(half);
  if (l.prior_travel_s == travel_s) return;
  const float ratio = l.travel_s > 0.0f ? travel_s / l.travel_s : 1.0f;
  if (l.pulses > 0 && (ratio > kRelearnTravelFactor || ratio < 1.0f / kRelearnTravelFactor)) {
    const TwoParameterRls::State taught = l.rls.state();
    l.rls.reset(taught.theta1, taught.theta2, kFlowSpread * l.prior_flow_g_s, kLossSpreadS * l.prior_flow_g_s);
  }
  l.prior_travel_s = travel_s;
  l.travel_s = travel_s;
}

void TopUpPulseLaw::learn(const Pulse& pulse, float delivered_g) {
  Law& l = law(pulse.command == ValveCommand::half);
  observe(l, pulse.seconds, delivered_g);
  learn_travel(l, pulse.seconds, delivered_g);
  if (l.pulses < 255) ++l.pulses;
}

float TopUpPulseLaw::seconds_for(const Law& law, float mass_g) const {
  // Solve m = q e - c for the open time e; below the loss's build-up, m = (q - c / build) e.
  const float q = law.rls.state().theta1, c = law.rls.state().theta2;
  float open_s = q > 0.0f ? (mass_g + c) / q : 0.0f;
  const float short_slope = q - c / kLossBuildS;
  if (open_s < kLossBuildS && short_slope > 0.0f) open_s = mass_g / short_slope;
  const float seconds = pulse_seconds(law, open_s > 0.0f ? open_s : 0.0f);
  return seconds < kShortestPulseS ? kShortestPulseS : (seconds > max_pulse_s_ ? max_pulse_s_ : seconds);
}

// The law's standard deviation of a pulse's mass: what it is still unsure of.
float TopUpPulseLaw::unsure_g(const Law& law, float seconds) const {
  const TwoParameterRls::State& s = law.rls.state();
  const float x1 = open_seconds(law, seconds), x2 = loss_regressor(x1);
  const float variance = x1 * (s.p11 * x1 + s.p12 * x2) + x2 * (s.p12 * x1 + s.p22 * x2);
  return variance > 0.0f ? std::sqrt(variance) : 0.0f;
}

// ... and the valve's jitter at its flow.
float TopUpPulseLaw::spread_g(const Law& law, float seconds) const {
  return unsure_g(law, seconds) + kJitterS * law.rls.state().theta1;
}

float TopUpPulseLaw::aim_g(const Law& law, float deficit_g, const Outlook& outlook) const {
  const bool last = outlook.pulses_after == 0;
  if (last && law.pulses == 0) return deficit_g;
  if (last) {
    const float aim = deficit_g - kLastAimSigmas * unsure_g(law, seconds_for(law, deficit_g));
    return aim > kLeastAim * deficit_g ? aim : kLeastAim * deficit_g;
  }
  if (seconds_for(law, kLaterAim * deficit_g) > kLongPulseS) return kLeastAim * deficit_g;
  // A law no pulse taught (only the dose's long opening, whose start-up loss is no short pulse's):
  // the fixed share, whatever it thinks it knows.
  if (law.pulses == 0) return kFirstAim * deficit_g;
  if (outlook.pulses_after == 1 && outlook.limit_g > 0.0f) {
    return risk_aim_g(law, deficit_g, outlook);
  }
  return sure_aim_g(law, deficit_g);
}

float TopUpPulseLaw::sure_aim_g(const Law& law, float deficit_g) const {
  const float most = kLaterAim * deficit_g;
  const float sure = deficit_g - kAimSigmas * spread_g(law, seconds_for(law, most));
  const float aim = sure < most ? sure : most;
  return aim > kLeastAim * deficit_g ? aim : kLeastAim * deficit_g;
}

// The aim, from kLeastAim of the deficit to all of it, whose fill is likeliest within the class's
// limit, with what it costs in time and in the series' mean weighed in when the outlook gives them;
// of aims as likely, the one that leaves the least for the last pulse. The last pulse's spread is
// the law's at a tenth and at half the deficit, taken as a line.
float TopUpPulseLaw::risk_aim_g(const Law& law, float deficit_g, const Outlook& outlook) const {
  const float limit_g = outlook.limit_g;
  const bool weighs_time_and_mean = outlook.mean_limit_g > 0.0f;
  const float small_g = 0.1f * deficit_g, large_g = 0.5f * deficit_g;
  const float small_spread_g = spread_g(law, seconds_for(law, small_g));
  const float per_g = (spread_g(law, seconds_for(law, large_g)) - small_spread_g) / (large_g - small_g);
  const LastPulseSpread last{small_spread_g - per_g * small_g, per_g};
  float best_aim_g = kLeastAim * deficit_g, best_cost = 2.0f;
  for (int i = 0; i <= kRiskAimSteps; ++i) {
    const float aim = (kLeastAim + (1.0f - kLeastAim) * float(i) / float(kRiskAimSteps)) * deficit_g;
    const float spread = spread_g(law, seconds_for(law, aim));
    float cost = pulse_pair_miss_chance(deficit_g, aim, spread, last, limit_g);
    // The weighed chances only add: an aim already costlier than the best needs neither (the
    // Cortex-M's jiffy that sizes the pulse has room for few exponentials).
    if (weighs_time_and_mean && cost <= best_cost) {
      const float left_g = deficit_g - aim;
      cost += kAnotherPulseWorth * pulse_ends_short_chance(left_g, spread, outlook.accepted_short_g) +
              kAboveMeanLimitWorth * pulse_ends_over_chance(left_g, spread, outlook.mean_limit_g);
    }
    if (cost <= best_cost) {
      best_cost = cost;
      best_aim_g = aim;
    }
  }
  return best_aim_g;
}

// Half open, unless the longest pulse at half open's flow could not bring what is missing (and the
// dose told the full-open flow): a pulse's mass is off by the valve's timing jitter times the flow
// where the gate turns back, and half open never turns above half open's flow.
void TopUpPulseLaw::choose(float deficit_g) {
  const bool half_can = deficit_g <= max_pulse_s_ * half_.rls.state().theta1;
  half_open_ = (half_can || full_.seen == 0) && half_.prior_flow_g_s > 0.0f;
  chosen_ = true;
}

TopUpPulseLaw::Pulse TopUpPulseLaw::size(float deficit_g, bool last) {
  Outlook outlook;
  if (last) outlook.pulses_after = 0;
  return size(deficit_g, outlook);
}

TopUpPulseLaw::Pulse TopUpPulseLaw::size(float deficit_g, const Outlook& outlook) {
  const float deficit = deficit_g > 0.0f ? deficit_g : 0.0f;
  if (!chosen_) choose(deficit);
  const Law& chosen = law(half_open_);
  Pulse pulse;
  pulse.command = half_open_ ? ValveCommand::half : ValveCommand::open;
  pulse.seconds = seconds_for(chosen, aim_g(chosen, deficit, outlook));
  pulse.expected_g = expected_g(half_open_, pulse.seconds);
  return pulse;
}

float TopUpPulseLaw::expected_g(bool half, float seconds) const {
  const float m = predicted_g(law(half), seconds);
  return m > 0.0f ? m : 0.0f;
}

}  // namespace dynweigh::firmware
