#include "dynweigh/firmware/dosing_cycle.hpp"

#include <cmath>
#include <cstddef>

#include "dynweigh/model/oiml_r61_limits.hpp"

namespace dynweigh::firmware {
namespace {
// Fills of the open-time law before a blind close planned on it counts as taught.
constexpr std::uint16_t kLawFillsForPlan = 2;
// Dynamic certification: the fit's standard error of W within 1.5 divisions, and five successive
// estimates agreeing within half a division. The least-squares error is pessimistic here (its
// regressors carry the noise too): the bench measures the certified result against the truth
// (claim_error_max_g): at most 1.2 d off, rounding to the division included, over its sweep.
constexpr float kCertifiedErrorG = 1.5f;
constexpr float kAgreementG = 0.5f;
constexpr float kConfidenceSigmas = 1.0f;
// A fit whose residuals' rms is above kMisfitNoiseFactor x the scale's noise at rest, plus
// kMisfitFloorG, leaves something in the reading that no ringing explains: an impact still relaxing
// (its force dies away over tens of milliseconds after the last grain; the fit's W follows it down
// slowly, and five estimates agreed while still 3 to 5 g high on `fine-powder`), an avalanche on
// the pile. Its estimate is not certified, and the window drops its kMisfitDropSamples oldest
// samples, down to kMisfitKeptSamples: the next fit starts where less of it is left
// (docs/strategies.md, Dynamic weighing). Only while the reading moves: a reading that froze in
// mid-settling would fit perfectly once the window held nothing else, certified before it is found
// frozen (kFrozenSamples) and a pulse sized on it.
constexpr float kMisfitNoiseFactor = 2.0f;
constexpr float kMisfitFloorG = 0.3f;
constexpr std::size_t kMisfitDropSamples = 8;
constexpr std::size_t kMisfitKeptSamples = 24;
// After the computed landing of the last grain (the valve shut, the last grains fallen from rest):
// the dispersion relaxation and the jitter of the valve's dead time.
constexpr float kLandingMarginS = 0.03f;
// A close made before the stream was measured knows the flow only from its prior (the density may
// be off by 40 %): a top-up then sizes its first pulse from the prior taken this much high, so that it
// falls short rather than over.
constexpr float kBlindFlowMargin = 1.4f;
constexpr float kNoStreamYetFactor = 2.0f;
// The longest pulse sized from a measured flow: each aims short of the deficit anyway.
constexpr float kLongestSizedPulseS = 2.0f;
}  // namespace

void DosingCycle::configure(const Parameters& p) {
  model_.configure(p);
  jiffy_s_ = p.get(ParameterId::jiffy_ms) / 1000.0f;
  blind_horizon_jiffies_ = std::uint32_t(std::ceil(kStaleSampleLimitMs / p.get(ParameterId::jiffy_ms)));
  preact_g_ = p.get(ParameterId::preact_g);
  two_stage_.configure(p);
  pac_.configure(p);
  flow_preact_.configure(p);
  model_fine_s_ = p.get(ParameterId::model_fine_s);
  planner_.configure(p.get(ParameterId::oiml_class), model_.half_flow_ratio(), jiffy_s_);
  timeout_s_ = p.get(ParameterId::dose_timeout_s);
  subjiffy_ = p.get(ParameterId::subjiffy) > 0.5f;
  certify_mode_ = p.certify();
  const std::uint32_t stable_jiffies = std::uint32_t(p.get(ParameterId::stable_ms) / p.get(ParameterId::jiffy_ms));
  stable_.configure(p.get(ParameterId::stable_band_g), stable_jiffies);
  standstill_.configure(p.get(ParameterId::stable_band_g), stable_jiffies);
}

void DosingCycle::watch_standstill(float filtered_weight_g, float net_weight_g, float counts_per_gram) {
  standstill_.push(filtered_weight_g);
  // The noise in grams holds for one span: a new calibration forgets it, and without one the
  // weights are 0 and tell nothing.
  if (counts_per_gram != noise_span_) {
    rest_noise_ = RestNoise{};
    noise_span_ = counts_per_gram;
  }
  if (!(counts_per_gram > 0.0f)) return;
  if (standstill_.count() == 1) rest_noise_.restart();  // the weight moved: a new rest begins
  rest_noise_.push(net_weight_g - filtered_weight_g);
}

void DosingCycle::start(std::int32_t target_g, DosingStrategy strategy, const LearningTable* learning) {
  result_ = DoseResult{};
  learning_ = learning;
  learning_key_ = LearningKey{};
  result_.target_g = target_g;
  result_.strategy = strategy;
  jiffies_ = 0;
  last_prediction_g_ = 0.0f;
  valve_delay_100us_ = 0;
  stable_.reset();
  settling_fit_.reset();
  estimates_ = 0;
  blind_jiffies_ = 0;
  top_up_flow_g_s_ = 0.0f;
  topping_up_ = false;
  planner_.start();
  fine_point_passed_ = false;
  plan_ = PlanChoice{};
  close_sigma_g_ = 0.0f;
  forget_sizing_reading();
  close_taught_ = false;
  frozen_reading_ = false;
  still_samples_ = 0;
  phase_ = Phase::dosing;
  valve_ = ValveCommand::closed;
  awaiting_rest_ = true;  // step() opens, in this very jiffy if its sample finds the scale at rest
}

void DosingCycle::open_from_rest() {
  awaiting_rest_ = false;
  open_jiffy_ = jiffies_;
  start_weight_g_ = standstill_.mean();
  rest_noise_.keep_this_rest();
  rest_noise_g_ = rest_noise_.rms_g();
  model_.start(start_weight_g_, float(result_.target_g));
  // Once a dose: it does not change within one, and a root each jiffy costs the Cortex-M budget.
  measured_sigma_scale_ = model_.fill_law().measured_sigma_scale();
  two_stage_.start(float(result_.target_g));
  pac_.start(float(result_.target_g));
  flow_preact_.start(float(result_.target_g));
  valve_ = ValveCommand::open;
}

bool DosingCycle::decide_model(float net_weight_g) {
  const float target = float(result_.target_g);
  last_prediction_g_ = model_.observe(net_weight_g);
  // Learning also corrects a close made on the prior (a small target, closed before the stream could
  // be measured): there the unknown start-up of the flow is the whole residual. The flow key is then
  // the prior's, which every such fill shares.
  if (result_.strategy == DosingStrategy::learn && learning_) {
    learning_key_ = make_learning_key(target, model_.fall_height_m(start_weight_g_ + target),
                                      model_.measured_flow_kg_s());
    last_prediction_g_ += learning_->correction_g(learning_key_);
  }
  const float growth = model_.growth_per_jiffy_g();
  const float aim = target - plan_step(growth);
  // A half-open fine feed for the last fine_s of full flow: less material in flight means less of
  // the flow's fluctuation left unobserved at the close. Where the plan chose it, or on every
  // measured dose where `model_fine_s` is set.
  // Once the plan's switch point has passed it is no longer a plan: nothing left to time.
  const bool may_switch = !model_.fine_feeding() && (model_fine_s_ > 0.0f || !fine_point_passed_);
  const bool at_fine_point = may_switch && last_prediction_g_ + growth * fine_lead_s() / jiffy_s_ >= aim;
  const bool fine_wanted = model_fine_s_ > 0.0f || plan_.plan == DosePlan::fine;
  if (at_fine_point && fine_wanted && model_.measuring()) {
    model_.switch_to_half(last_prediction_g_);
    plan_.plan = DosePlan::fine;
    valve_ = ValveCommand::half;
    return false;
  }
  if (at_fine_point) fine_point_passed_ = true;
  const float earliest = model_.earliest_close_fraction();
  if (model_.beyond_the_law() && earliest <= 0.0f) {
    model_.closed(0.0f);
    return true;
  }
  if (!subjiffy_) {
    // On the jiffy grid, close at the jiffy whose half-way point the prediction crosses.
    const bool close = earliest <= 0.0f && last_prediction_g_ + 0.5f * growth >= aim;
    if (close) model_.closed(0.0f);
    return close;
  }
  if (last_prediction_g_ + growth < aim || earliest > 0.99f) return false;
  // The aim falls within the coming jiffy: close exactly when the prediction reaches it.
  const float fraction = growth > 0.0f ? (aim - last_prediction_g_) / growth : 0.0f;
  const float lowest = earliest > 0.0f ? earliest : 0.0f;
  const float clamped = fraction < lowest ? lowest : (fraction > 0.99f ? 0.99f : fraction);
  valve_delay_100us_ = std::uint8_t(std::lround(clamped * jiffy_s_ * 1e4f));
  if (valve_delay_100us_ > 99) valve_delay_100us_ = 99;
  model_.closed(float(valve_delay_100us_) / (jiffy_s_ * 1e4f));
  return true;
}

// How many seconds of full flow before the target a fine feed begins: `model_fine_s`, or what the
// half-open stream needs to land and be measured again before the close, at half open's flow.
float DosingCycle::fine_lead_s() const {
  if (model_fine_s_ > 0.0f) return model_fine_s_;
  return model_.half_flow_ratio() * (model_.settle_delay_s() + DosePlanner::kFineMeasureS);
}

// The model's plan for a close now (dose_plan.hpp); returns how far short of the target to aim.
// Once the fine feed runs, the plan is kept: the half-open stream is measured again anyway.
float DosingCycle::plan_step(float growth_g_per_jiffy) {
  if (result_.strategy != DosingStrategy::model || model_.fine_feeding()) return plan_.margin_g;
  if (model_.measuring()) planner_.observe_rate(growth_g_per_jiffy);
  const float in_flight_g = growth_g_per_jiffy / jiffy_s_ * model_.settle_delay_s();
  // Open for twice the time the first grains need to land and still nothing measured: no stream
  // (a valve stuck shut, an empty silo) rather than a close too early to see one. Aiming short
  // then only closes sooner on a prior the supervision is still checking: plan as before.
  const float open_s = float(jiffies_ - open_jiffy_) * jiffy_s_;
  if (!model_.measuring() && open_s > kNoStreamYetFactor * model_.settle_delay_s()) {
    plan_ = PlanChoice{};
    return 0.0f;
  }
  const bool law_taught = model_.fill_law().learned().open_time_law.fills >= kLawFillsForPlan;
  const bool let_through_taught = model_.fill_law().learned().residual_fills > 0;
  const float let_through_sigma_g =
      let_through_taught ? 0.0f : DosePlanner::kUnlearnedLetThroughS * growth_g_per_jiffy / jiffy_s_;
  const FineFeedOutlook fine{!fine_point_passed_, model_fine_s_ > 0.0f, growth_g_per_jiffy / jiffy_s_};
  plan_ = planner_.choose(float(result_.target_g), last_prediction_g_, in_flight_g, model_.measuring(), law_taught,
                          model_.settle_delay_s(), let_through_sigma_g, measured_sigma_scale_, fine);
  // What the close teaches of the scale is measured against the model's own uncertainty.
  close_sigma_g_ = model_.measuring() ? plan_.sigma_g / measured_sigma_scale_ : 0.0f;
  return plan_.margin_g;
}

bool DosingCycle::decide_preact(float filtered_weight_g, float preact_g) {
  last_prediction_g_ = filtered_weight_g - start_weight_g_ + preact_g;
  return last_prediction_g_ >= float(result_.target_g);
}

bool DosingCycle::decide_twostage(float filtered_weight_g) {
  const ValveCommand wanted = two_stage_.step(filtered_weight_g - start_weight_g_);
  last_prediction_g_ = two_stage_.prediction_g();
  if (wanted == ValveCommand::closed) return true;
  valve_ = wanted;
  return false;
}

bool DosingCycle::decide_flow_baseline(float filtered_weight_g) {
  const float filled_g = filtered_weight_g - start_weight_g_;
  const bool pac = result_.strategy == DosingStrategy::pac;
  const CloseDecision d = pac ? pac_.step(filled_g) : flow_preact_.step(filled_g);
  last_prediction_g_ = pac ? pac_.prediction_g() : flow_preact_.prediction_g();
  // On the jiffy grid, close at the jiffy whose half-way point the prediction crosses.
  if (d.close && !subjiffy_) return d.fraction < 0.5f;
  if (d.close) {
    const long delay = std::lround(d.fraction * jiffy_s_ * 1e4f);
    valve_delay_100us_ = std::uint8_t(delay > 99 ? 99 : delay);
  }
  return d.close;
}

void DosingCycle::close_valve(float settle_delay_s) {
  if (phase_ == Phase::dosing) {
    keep_top_up_flow();
    // Full open from the open command to this close (a fine feed is no such pulse).
    const bool one_pulse = !model_.fine_feeding() && valve_ == ValveCommand::open;
    dose_open_s_ = one_pulse ? float(jiffies_ - open_jiffy_) * jiffy_s_ + float(valve_delay_100us_) * 1e-4f : 0.0f;
  }
  // A valve still on its way open, or a pulse too short to part the gate, may have let nothing
  // through: a reading that stands still after it is no proof of a frozen converter.
  grains_in_flight_ = phase_ == Phase::dosing ? valve_could_deliver_ : pulse_.seconds >= pulse_travel_s();
  valve_ = ValveCommand::closed;
  phase_ = Phase::settling;
  if (!topping_up_) result_.cutoff_jiffy = jiffies_;
  closed_jiffy_ = jiffies_;
  moved_since_close_ = false;
  settle_from_jiffy_ = jiffies_ + std::uint32_t(std::ceil((settle_delay_s + kLandingMarginS) / jiffy_s_));
}

// The full-open flow a top-up of this dose is sized from: the model's measured one (from half open
// after a fine feed), or its prior taken high when it closed before measuring.
void DosingCycle::keep_top_up_flow() {
  top_up_flow_g_s_ = 0.0f;
  if (result_.strategy != DosingStrategy::model && result_.strategy != DosingStrategy::learn) return;
  float flow_g_s = 1000.0f * model_.measured_flow_kg_s();
  if (model_.fine_feeding() && model_.half_flow_ratio() > 0.0f) flow_g_s /= model_.half_flow_ratio();
  if (!model_.measuring()) flow_g_s *= kBlindFlowMargin;
  top_up_flow_g_s_ = flow_g_s > 0.0f ? flow_g_s : 0.0f;
}

void DosingCycle::start_top_up(float deficit_g, float fixed_pulse_s, std::uint8_t pulses_after,
                               float accepted_short_g) {
  if (!topping_up_ && sizes_top_ups()) {
    top_up_law_.begin(top_up_flow_g_s_, model_.half_flow_ratio(), model_.stroke_timed_s(), kLongestSizedPulseS,
                      model_.gate_flow_shape());
    if (dose_open_s_ > 0.0f) top_up_law_.observe_dose(dose_open_s_, float(result_.final_g));
  }
  topping_up_ = true;
  if (sizes_top_ups()) {
    if (half_travel_s_ > 0.0f) top_up_law_.timed_travel(true, half_travel_s_);
    const float target_g = float(result_.target_g);
    const float mean_limit_g = accepted_short_g > 0.0f ? planner_.class_mean_limit_g(target_g) : 0.0f;
    pulse_ = top_up_law_.size(deficit_g, {pulses_after, planner_.class_limit_g(target_g), accepted_short_g, mean_limit_g});
  } else {
    pulse_ = TopUpPulseLaw::Pulse{ValveCommand::open, fixed_pulse_s, 0.0f};
  }
  // Whole jiffies from this one's output; a pulse off the grid opens late within the first jiffy.
  const float jiffies = pulse_.seconds / jiffy_s_;
  std::uint32_t whole = std::uint32_t(subjiffy_ ? std::ceil(jiffies) : std::round(jiffies));
  if (whole < 1) whole = 1;
  const float early_s = float(whole) * jiffy_s_ - pulse_.seconds;
  const long delay = subjiffy_ && early_s > 0.0f ? std::lround(early_s * 1e4f) : 0;
  valve_delay_100us_ = std::uint8_t(delay > 99 ? 99 : delay);
  pulse_end_jiffy_ = jiffies_ + whole;
  stable_.reset();
  settling_fit_.reset();
  estimates_ = 0;
  forget_sizing_reading();
  valve_ = pulse_.command;
  phase_ = Phase::pulsing;
}

// Between a close (or a pulse's end) and the computed landing of its last grain, the grains in
// flight land: the reading moves, noise or none. One that has not moved once in that time is frozen,
// and where grains were surely in flight the dose ends in the fault (step()); one that stands still
// for kFrozenSamples samples once they have landed is frozen too (a live load cell's noise and the
// platform's ringing move it every few samples), or a scale without noise: no pulse is sized on it.
bool DosingCycle::watch_for_frozen_reading(float net_weight_g, bool fresh) {
  if (!fresh) return false;
  const bool still = net_weight_g == last_net_g_;
  bool froze_while_landing = false;
  if (phase_ == Phase::settling) {
    if (!still) moved_since_close_ = true;
    if (jiffies_ == settle_from_jiffy_ && !moved_since_close_) {
      frozen_reading_ = true;
      froze_while_landing = grains_in_flight_;
    }
    still_samples_ = still && jiffies_ > settle_from_jiffy_ ? still_samples_ + 1 : 0;
    if (still_samples_ >= kFrozenSamples) frozen_reading_ = true;
  } else {
    still_samples_ = 0;
  }
  last_net_g_ = net_weight_g;
  return froze_while_landing;
}

PlanChoice DosingCycle::plan() const {
  if (result_.strategy == DosingStrategy::model || result_.strategy == DosingStrategy::learn) return plan_;
  PlanChoice baseline;
  baseline.plan = result_.strategy == DosingStrategy::twostage ? DosePlan::fine : DosePlan::full;
  return baseline;
}

// Once per dose, from the close's first certified reading: a reading that only sized a pulse and
// was then certified in full after all (certify_in_full) does not teach the close twice.
void DosingCycle::learn_from_close() {
  close_taught_ = true;
  if (result_.strategy == DosingStrategy::twostage) two_stage_.learn(float(result_.final_g));
  if (result_.strategy == DosingStrategy::pac) pac_.learn(float(result_.final_g));
  if (result_.strategy == DosingStrategy::flowpreact) flow_preact_.learn(float(result_.final_g));
  if (result_.strategy == DosingStrategy::model || result_.strategy == DosingStrategy::learn) {
    model_.learn(float(result_.final_g), close_sigma_g_);
  }
}

float DosingCycle::pulse_travel_s() const {
  const float position = pulse_.command == ValveCommand::half ? 0.5f : 1.0f;
  return position * model_.stroke_in_use_s_now();
}

PulseVerdict DosingCycle::last_pulse_verdict(float delivered_g) const {
  return judge_pulse(pulse_.expected_g, delivered_g, pulse_.seconds, pulse_travel_s(), sizes_top_ups());
}

bool DosingCycle::pulse_moved_nothing(float delivered_g) const {
  return last_pulse_verdict(delivered_g) == PulseVerdict::moved_nothing;
}

bool DosingCycle::learn_top_up(float delivered_g) {
  if (pulse_moved_nothing(delivered_g)) return false;
  if (sizes_top_ups()) top_up_law_.learn(pulse_, delivered_g > 0.0f ? delivered_g : 0.0f);
  return true;
}

bool DosingCycle::dose_delivered_nothing() const { return float(result_.final_g) <= nothing_delivered_limit_g(); }

float DosingCycle::nothing_delivered_limit_g() const {
  return kNothingDeliveredClass * model::oiml_r61_x1_limits(float(result_.target_g)).initial_verification_g;
}

DosingCycle::Outcome DosingCycle::step_pulse() {
  if (jiffies_ >= pulse_end_jiffy_) close_valve(model_.settle_delay_s());
  return Outcome::running;
}

bool DosingCycle::certify_dynamically() const {
  if (certify_mode_ == CertifyMode::dynamic) return true;
  if (certify_mode_ == CertifyMode::stable) return false;
  return result_.strategy == DosingStrategy::model || result_.strategy == DosingStrategy::learn;
}

bool DosingCycle::certify(float net_weight_g, float filtered_weight_g) {
  reading_sizes_only_ = false;
  if (stable_.push(filtered_weight_g)) {
    result_.final_g = std::int32_t(std::lround(stable_.mean() - start_weight_g_));
    return true;
  }
  if (!certify_dynamically()) return false;
  settling_fit_.push(net_weight_g);
  const auto estimate = settling_fit_.fit();
  if (!estimate.valid) return false;
  if (!settling_fit_describes_reading(estimate.residual_rms)) return false;
  recent_estimates_[estimates_ % kAgreementJiffies] = estimate.final_value;
  ++estimates_;
  const RecentEstimates recent{recent_estimates_, kAgreementJiffies, estimates_};
  reading_sizes_only_ = sizes_next_pulse(recent, estimate.standard_error, estimate.final_value);
  const bool certified = kConfidenceSigmas * estimate.standard_error <= kCertifiedErrorG &&
                         newest_estimates_spread_g(recent, kAgreementJiffies) <= kAgreementG;
  if (!reading_sizes_only_ && !certified) return false;
  reading_sizes_only_ = reading_sizes_only_ && !certified;
  result_.final_g = std::int32_t(std::lround(estimate.final_value - start_weight_g_));
  return true;
}

// A fill that a pulse may follow, short by more than it is left: its reading need only size that
// pulse (sizing_reading.hpp). The model tops up by itself below what its plan accepts; another
// strategy where `tol_action topup` tops up below the reject band.
bool DosingCycle::sizes_next_pulse(const RecentEstimates& recent, float standard_error_g, float final_value) const {
  const bool model = result_.strategy == DosingStrategy::model;
  const float left_short_g = model ? model_top_up_shortfall_g(plan_.plan, sizing_warn_low_g_) : sizing_reject_low_g_;
  if (!((model ? sizing_warn_low_g_ : sizing_reject_low_g_) > 0.0f)) return false;
  const float deficit_g = float(result_.target_g) - (final_value - start_weight_g_);
  return reading_sizes_pulse(recent, standard_error_g, deficit_g, left_short_g);
}

void DosingCycle::certify_in_full() {
  forget_sizing_reading();
  phase_ = Phase::settling;
}

void DosingCycle::forget_sizing_reading() {
  allow_sizing_reading(0.0f, 0.0f);
  reading_sizes_only_ = false;
}

// Whether the fit's residuals are within what the scale's noise at rest explains; else the window
// starts later, and the estimates agree anew.
bool DosingCycle::settling_fit_describes_reading(float residual_rms_g) {
  if (residual_rms_g <= kMisfitNoiseFactor * rest_noise_g_ + kMisfitFloorG) return true;
  const std::size_t kept = settling_fit_.count();
  if (kept > kMisfitKeptSamples && still_samples_ == 0) {
    const std::size_t excess = kept - kMisfitKeptSamples;
    settling_fit_.drop_oldest(excess < kMisfitDropSamples ? excess : kMisfitDropSamples);
  }
  estimates_ = 0;
  return false;
}

DosingCycle::Outcome DosingCycle::step(float net_weight_g, float filtered_weight_g, bool fresh) {
  if (phase_ == Phase::idle) return Outcome::running;
  ++jiffies_;
  valve_delay_100us_ = 0;
  if (watch_for_frozen_reading(net_weight_g, fresh)) {
    abort();
    return Outcome::reading_frozen;
  }
  const float elapsed_s = float(jiffies_) * jiffy_s_;
  if (phase_ == Phase::dosing && awaiting_rest_) {
    if (!standstill_.stable()) {
      if (elapsed_s <= settle_limit_s_) return Outcome::running;
      abort();
      return Outcome::never_stable;
    }
    open_from_rest();  // and decide in this jiffy, as a dose that found the scale at rest does
  }
  if (phase_ == Phase::pulsing) return step_pulse();
  if (phase_ == Phase::dosing && !fresh) {
    // No sample: nothing to decide on. If the fill could reach the target before the supervisor
    // declares the sensor stale, close now: an early close underfills, a blind one overdoses.
    ++blind_jiffies_;
    const float growth = model_.growth_per_jiffy_g();
    if (last_prediction_g_ + growth * float(blind_jiffies_ + blind_horizon_jiffies_) >= float(result_.target_g)) {
      close_valve(model_.settle_delay_s());
    }
    return Outcome::running;
  }
  blind_jiffies_ = 0;
  if (phase_ == Phase::dosing) {
    bool close = false;
    switch (result_.strategy) {
      case DosingStrategy::model:
      case DosingStrategy::learn:
        close = decide_model(net_weight_g);
        break;
      case DosingStrategy::preact:
        close = decide_preact(filtered_weight_g, preact_g_);
        break;
      case DosingStrategy::twostage:
        close = decide_twostage(filtered_weight_g);
        break;
      case DosingStrategy::pac:
      case DosingStrategy::flowpreact:
        close = decide_flow_baseline(filtered_weight_g);
        break;
    }
    if (close) {
      close_valve(model_.settle_delay_s());
    } else if (elapsed_s > timeout_s_) {
      abort();
      return Outcome::timed_out;
    }
    return Outcome::running;
  }
  // Settling: only once the last grain has landed does the reading describe the whole fill.
  if (jiffies_ < settle_from_jiffy_) return Outcome::running;
  if (certify(net_weight_g, filtered_weight_g)) {
    result_.time_ms = std::uint32_t(std::lround(elapsed_s * 1000.0f));
    phase_ = Phase::idle;
    if (topping_up_) return Outcome::certified;  // the strategies learn from their own close only
    if (delivered_nothing()) return Outcome::nothing_delivered;  // teaches nothing
    if (!close_taught_) learn_from_close();
    return Outcome::certified;
  }
  if (float(jiffies_ - closed_jiffy_) * jiffy_s_ > settle_limit_s_) {
    abort();
    return Outcome::never_stable;
  }
  return Outcome::running;
}

bool DosingCycle::delivered_nothing() const {
  const float limit = nothing_delivered_limit_g();
  const float final_g = float(result_.final_g);
  const bool share_of_its_prediction =
      last_prediction_g_ > limit && final_g > kNothingDeliveredShare * last_prediction_g_;
  return valve_could_deliver_ && final_g <= limit && !share_of_its_prediction;
}

}  // namespace dynweigh::firmware
