#include "dynweigh/firmware/model_cutoff.hpp"

#include <cmath>

#include "dynweigh/model/bore_area.hpp"
#include "dynweigh/model/platform_frequency.hpp"
#include "dynweigh/model/valve_let_through.hpp"

namespace dynweigh::firmware {
namespace {
template <typename Scalar>
constexpr Scalar kGravity = Scalar(9.81);
// The material is unknown until it flows: Beverloo's constants for a typical free-flowing sand
// (docs/physics.md, Beverloo) give the prior; the measured flow replaces it after the first impact.
template <typename Scalar>
constexpr model::BeverlooMaterial<Scalar> prior_material(Scalar bulk_density) {
  return {Scalar(0.58), Scalar(1.5), Scalar(0.0005), bulk_density};
}
// the default scene's platform (docs/scenes.md); the observer barely depends on it (damping 0.02..0.1 changes its static
// estimate by a few grams), so it is not a parameter.
template <typename Scalar>
constexpr Scalar kPlatformDamping = Scalar(0.05);
// The silo's flow wanders by ~3 % over 0.15 s and each jiffy's landing scatters by ~7 % about it
// (the default scene; docs/physics.md): the observer's noise in proportion to the flow.
template <typename Scalar>
constexpr Scalar kRateWalkPerJiffy = Scalar(0.0125);
template <typename Scalar>
constexpr Scalar kLandingScatter = Scalar(0.07);
// The load cell's noise and its 1 d rounding, in grams: the opening estimator's floor.
template <typename Scalar>
constexpr Scalar kSampleNoiseG = Scalar(0.5);
// The impact's signature is read this long after the stream is whole: the observer has settled and
// the landed mass is still small beside the impulse.
constexpr std::uint32_t kSignatureJiffies = 20;
template <typename Scalar>
constexpr Scalar kSignatureMinimumFlow = Scalar(0.2);  // of the prior flow
// The dead time learned from the first impacts: a running mean over this many doses, used from the
// second dose on when it is off the datasheet by more than 6 ms (2 ms jitter, ~2 ms of estimate).
constexpr std::uint32_t kDeadTimeMemory = 8;
constexpr std::uint32_t kDeadTimeMinDoses = 2;
template <typename Scalar>
constexpr Scalar kDeadTimeDeadbandS = Scalar(0.006);
// The stroke from the feedback: the time to the end position, less the dead time, is used once it is
// off the datasheet by more than a jiffy of the feedback's resolution and the dead time's error.
template <typename Scalar>
constexpr Scalar kStrokeDeadbandS = Scalar(0.015);
// The first impact's sample holds a part-jiffy of landing: a few samples more tell S from k L.
constexpr std::uint32_t kObserverSettleJiffies = 3;
}  // namespace

template <typename Scalar>
void BasicModelCutoff<Scalar>::configure(const Parameters& p) {
  const Scalar g = kGravity<Scalar>;
  const auto get = [&p](ParameterId id) { return Scalar(p.get(id)); };
  jiffy_s_ = get(ParameterId::jiffy_ms) / Scalar(1000);
  const Scalar bore_m = get(ParameterId::bore_mm) / Scalar(1000);
  const Scalar density = get(ParameterId::density);
  const Scalar dead_s = get(ParameterId::valve_dead_ms) / Scalar(1000);
  const Scalar stroke_s = get(ParameterId::valve_stroke_ms) / Scalar(1000);
  const auto material = prior_material(density);

  geometry_.g = g;
  geometry_.bore_area_m2 = model::bore_area_m2(bore_m);
  geometry_.bulk_density = density;
  geometry_.orifice_to_floor_m = get(ParameterId::fall_mm) / Scalar(1000);
  geometry_.pile.container_diameter_m = get(ParameterId::container_mm) / Scalar(1000);
  geometry_.pile.repose_angle_rad = get(ParameterId::repose_deg) * Scalar(M_PI) / Scalar(180);
  geometry_.pile.bulk_density = density;
  geometry_.pile_grows = p.get(ParameterId::pile_rise) > 0.5f;
  full_area_m2_ = geometry_.bore_area_m2;
  material_ = material;
  bore_m_ = bore_m;
  stroke_s_ = stroke_s;
  configured_dead_s_ = dead_s;
  measured_dead_s_ = dead_s;
  dead_time_doses_ = 0;
  const Scalar full_rate = model::discharge_at_stroke_kg_s(material, g, bore_m, Scalar(1));
  const Scalar half_rate = model::discharge_at_stroke_kg_s(material, g, bore_m, Scalar(0.5));
  half_flow_ratio_ = full_rate > Scalar(0) ? half_rate / full_rate : Scalar(0.5);
  prior_rate_kg_s_ = model::beverloo_discharge_kg_s(material, g, bore_m);
  measured_travel_strokes_ = 0;
  set_valve_timing(dead_s, stroke_s);
  settle_jiffies_ = std::uint32_t(p.get(ParameterId::impact_settle_ms) / p.get(ParameterId::jiffy_ms));
  fit_.set_window(std::size_t(p.get(ParameterId::model_window_ms) / p.get(ParameterId::jiffy_ms)));
  // 20 d, or what the prior flow brings in two jiffies if that is more: a clear sign of flow.
  impact_threshold_g_ = std::fmax(Scalar(20), Scalar(2000) * prior_rate_kg_s_ * jiffy_s_);

  use_observer_ = p.get(ParameterId::model_estimator) > 0.5f;
  platform_hz_ = get(ParameterId::platform_hz);
  platform_kg_ = get(ParameterId::platform_kg);
  // The plant's and a real platform's load cell carry the damper's force too.
  opening_ = model::OpeningEstimator<Scalar>(
      model::PlatformResponse<Scalar>{platform_hz_, kPlatformDamping<Scalar>, platform_hz_ > Scalar(0)});
  const Scalar prior_per_jiffy = Scalar(1000) * prior_rate_kg_s_ * jiffy_s_;
  auto tuning = observer_.tuning();
  tuning.rate_walk_g = kRateWalkPerJiffy<Scalar> * prior_per_jiffy;
  tuning.landing_scatter_g = kLandingScatter<Scalar> * prior_per_jiffy;
  observer_.set_tuning(tuning);
  mean_window_jiffies_ = std::fmax(Scalar(1), get(ParameterId::model_window_ms) / get(ParameterId::jiffy_ms));
}

// The valve's timing: its let-through while closing from full and from half open, how long it takes
// to shut, and the flow missing at the opening. From the datasheet's dead time, or the one the scale
// has measured over the last doses once that is clearly different.
template <typename Scalar>
void BasicModelCutoff<Scalar>::set_valve_timing(Scalar dead_s, Scalar stroke_s) {
  const Scalar g = kGravity<Scalar>;
  effective_dead_s_ = dead_s;
  effective_stroke_s_ = stroke_s;
  // The first grains land a stroke before the whole stream does.
  established_jiffies_ = std::uint32_t(std::ceil(stroke_s / jiffy_s_)) + kObserverSettleJiffies;
  full_closing_flow_s_ = model::closing_flow_seconds(material_, g, bore_m_, dead_s, stroke_s);
  const Scalar full_rate = model::discharge_at_stroke_kg_s(material_, g, bore_m_, Scalar(1));
  const Scalar half_rate = full_rate * half_flow_ratio_;
  half_closing_flow_s_ =
      half_rate > Scalar(0)
          ? model::closing_flow_seconds(material_, g, bore_m_, dead_s, stroke_s, Scalar(0.5)) * full_rate / half_rate
          : dead_s;
  half_transition_s_ = dead_s + Scalar(0.25) * stroke_s;
  full_closing_duration_s_ = dead_s + stroke_s;
  half_closing_duration_s_ = dead_s + Scalar(0.5) * stroke_s;
  // Opening mirrors closing: the flow that is missing at the start equals the let-through at the end.
  opening_delay_s_ = dead_s + stroke_s - (full_closing_flow_s_ - dead_s);
  ramp_delay_s_ = std::fmax(Scalar(0), opening_delay_s_ - dead_s);
  geometry_.closing_flow_seconds = full_closing_flow_s_;
  closing_duration_s_ = full_closing_duration_s_;
}

// Each timed first impact joins a running mean of the valve's dead time (the last few doses); the
// model adopts it once two doses agree it is off the datasheet by more than the valve's jitter and
// the estimate's error can explain: a valve that has slowed with age, or a datasheet that was wrong.
template <typename Scalar>
void BasicModelCutoff<Scalar>::learn_dead_time(Scalar measured_s) {
  dead_time_doses_ = dead_time_doses_ < kDeadTimeMemory ? dead_time_doses_ + 1 : kDeadTimeMemory;
  measured_dead_s_ += (measured_s - measured_dead_s_) / Scalar(dead_time_doses_);
}

template <typename Scalar>
Scalar BasicModelCutoff<Scalar>::dead_time_in_use_s() const {
  const bool clearly_off = std::fabs(measured_dead_s_ - configured_dead_s_) > kDeadTimeDeadbandS<Scalar>;
  return dead_time_doses_ >= kDeadTimeMinDoses && clearly_off ? measured_dead_s_ : configured_dead_s_;
}

// The stroke as the feedback timed it: the time to the end position less the dead time. Feedback
// that reaches the end position before the valve can have moved (one that echoes the command) times
// nothing.
template <typename Scalar>
Scalar BasicModelCutoff<Scalar>::stroke_in_use_s(Scalar dead_s) const {
  if (measured_travel_strokes_ == 0) return stroke_s_;
  const Scalar measured = measured_travel_s_ - dead_s;
  if (!(measured > Scalar(0))) return stroke_s_;
  return std::fabs(measured - stroke_s_) > kStrokeDeadbandS<Scalar> ? measured : stroke_s_;
}

template <typename Scalar>
void BasicModelCutoff<Scalar>::start(Scalar start_weight_g) {
  const Scalar dead_s = dead_time_in_use_s();
  set_valve_timing(dead_s, stroke_in_use_s(dead_s));
  start_weight_g_ = start_weight_g;
  jiffies_ = 0;
  impacted_ = false;
  fine_ = false;
  geometry_.bore_area_m2 = full_area_m2_;
  geometry_.closing_flow_seconds = full_closing_flow_s_;
  closing_duration_s_ = full_closing_duration_s_;
  fit_.reset();
  observer_.stop();
  opening_.start(start_weight_g, jiffy_s_, kSampleNoiseG<Scalar>);
  estimates_ = DoseEstimates<Scalar>{};
  stream_confirmed_ = false;
  previous_sample_g_ = start_weight_g;
  rate_change_pending_ = false;
  growth_per_jiffy_g_ = prior_rate_kg_s_ * Scalar(1000) * jiffy_s_;
  last_fall_height_m_ = geometry_.orifice_to_floor_m;
  last_fall_time_s_ = model::fall_time(Scalar(0), kGravity<Scalar>, last_fall_height_m_);
  const Scalar prior_v0 = model::outflow_speed(prior_rate_kg_s_, full_area_m2_, geometry_.bulk_density);
  last_impact_speed_m_s_ = model::impact_speed(prior_v0, kGravity<Scalar>, last_fall_height_m_);
}

template <typename Scalar>
void BasicModelCutoff<Scalar>::switch_to_half(Scalar predicted_now_g) {
  fine_ = true;
  measured_full_rate_g_per_jiffy_ = growth_per_jiffy_g_;
  // The prediction now assumed a close from full open. From half open the valve lets less through,
  // and until it reaches half the flow is still (about) full.
  const Scalar full_per_s = measured_full_rate_g_per_jiffy_ / jiffy_s_;
  const Scalar half_per_s = full_per_s * half_flow_ratio_;
  predicted_at_switch_g_ = predicted_now_g - full_per_s * full_closing_flow_s_ + half_per_s * half_closing_flow_s_ +
                           (full_per_s - half_per_s) * half_transition_s_;
  switch_jiffy_ = jiffies_;
  geometry_.bore_area_m2 = full_area_m2_ * model::open_area_fraction(Scalar(0.5));
  geometry_.closing_flow_seconds = half_closing_flow_s_;
  closing_duration_s_ = half_closing_duration_s_;
  growth_per_jiffy_g_ *= half_flow_ratio_;
  fit_.reset();
  // The half-open stream lands a fall time after the valve has moved; fitting starts after that
  // and the impact's settling, like at the first impact.
  impact_jiffy_ = jiffies_ + std::uint32_t(std::ceil((half_transition_s_ + last_fall_time_s_) / jiffy_s_));
  measure_jiffy_ = impact_jiffy_ + established_jiffies_;
  rate_change_pending_ = true;
}

template <typename Scalar>
Scalar BasicModelCutoff<Scalar>::prior_prediction_g() const {
  if (fine_) {
    const Scalar since_switch = Scalar(jiffies_ - switch_jiffy_);
    return predicted_at_switch_g_ + since_switch * measured_full_rate_g_per_jiffy_ * half_flow_ratio_;
  }
  // The sample of the n-th jiffy shows n - 1 jiffies of the valve's being open.
  const Scalar open_s = Scalar(jiffies_ - 1) * jiffy_s_;
  const Scalar flowing_s = std::fmax(Scalar(0), open_s - opening_delay_s_);
  return Scalar(1000) * prior_rate_kg_s_ * (flowing_s + geometry_.closing_flow_seconds);
}

template <typename Scalar>
Scalar BasicModelCutoff<Scalar>::observe(Scalar net_weight_g) {
  ++jiffies_;
  estimate_opening(net_weight_g);
  const Scalar previous_g = previous_sample_g_;
  previous_sample_g_ = net_weight_g;
  const bool first_impact = !impacted_ && net_weight_g - start_weight_g_ >= impact_threshold_g_;
  if (first_impact) {
    impacted_ = true;
    impact_jiffy_ = jiffies_;
  }
  if (!use_observer_) {
    if (impacted_ && jiffies_ > impact_jiffy_ + settle_jiffies_) fit_.push(net_weight_g);
    return measuring() ? fitted_prediction_g() : prior_prediction_g();
  }
  if (first_impact) {
    const Scalar prior_per_jiffy = Scalar(1000) * prior_rate_kg_s_ * jiffy_s_;
    // The jump is the stream's momentum; what has come to rest is the part of a jiffy since the
    // first grains landed, which the valve's timing and the fall from rest tell best. A few grams
    // of error there would otherwise read as k times less rate.
    const Scalar prior_v0 = model::outflow_speed(prior_rate_kg_s_, full_area_m2_, geometry_.bulk_density);
    const Scalar fall_s = model::fall_time(prior_v0, kGravity<Scalar>, first_fall_height_m());
    const Scalar landed_s = Scalar(jiffies_ - 1) * jiffy_s_ - (opening_delay_s_ + fall_s);
    const Scalar landed_jiffies = std::fmin(std::fmax(landed_s / jiffy_s_, Scalar(0)), Scalar(1));
    observer_.start(net_weight_g, previous_g, start_weight_g_ + landed_jiffies * prior_per_jiffy, prior_per_jiffy,
                    Scalar(0.5) * prior_per_jiffy, prior_per_jiffy);
    measure_jiffy_ = jiffies_ + established_jiffies_;
  } else if (observer_.started()) {
    if (rate_change_pending_ && jiffies_ >= impact_jiffy_) {
      observer_.expect_rate_change(growth_per_jiffy_g_);
      rate_change_pending_ = false;
    }
    track_platform();
    observer_.observe(net_weight_g);
    average_rate();
  }
  return measuring() ? observed_prediction_g() : prior_prediction_g();
}

// The first impact, timed within the jiffy, and once the stream has run a while the impulse it
// brings: both for the console's `estimates`, which tell an installer whether the valve's timing
// and the geometry typed in agree with what the scale sees.
template <typename Scalar>
void BasicModelCutoff<Scalar>::estimate_opening(Scalar net_weight_g) {
  if (!estimates_.impact_timed) {
    // The sample of the n-th jiffy is the opening estimator's sample n - 1 (0 at the command).
    opening_.observe(net_weight_g);
    if (opening_.impact_found()) {
      estimates_.impact_timed = true;
      estimates_.first_impact_s = opening_.first_impact_s();
      estimates_.dead_time_s = opening_.dead_time_s(first_fall_height_m(), kGravity<Scalar>);
    }
  }
  if (!use_observer_ || !estimates_.impact_timed || stream_confirmed_ || !measuring() || fine_) return;
  if (jiffies_ < measure_jiffy_ + kSignatureJiffies) return;
  // No stream worth the name (a scale that does not see the flow, as in the hourglass): nothing to
  // read an impulse from, and the "first impact" was something else, not a lesson about the valve.
  const Scalar prior_per_jiffy = Scalar(1000) * prior_rate_kg_s_ * jiffy_s_;
  if (!(mean_rate_g_per_jiffy_ > kSignatureMinimumFlow<Scalar> * prior_per_jiffy)) return;
  stream_confirmed_ = true;
  learn_dead_time(estimates_.dead_time_s);
  const model::ImpactObservation<Scalar> seen{
      observer_.equilibrium_g() - start_weight_g_,
      Scalar(jiffies_ - 1) * jiffy_s_, mean_rate_g_per_jiffy_ / (Scalar(1000) * jiffy_s_),
      model::landing_start_s(estimates_.first_impact_s, ramp_delay_s_)};
  estimates_.signature = model::impact_signature(seen, full_area_m2_, geometry_.bulk_density, kGravity<Scalar>);
}

// The mean of the observed rate since the stream was whole (first impact, or the fine feed's
// landing), then a running mean over `model_window_ms`.
template <typename Scalar>
void BasicModelCutoff<Scalar>::average_rate() {
  if (jiffies_ < measure_jiffy_) return;
  const Scalar averaged = Scalar(jiffies_ - measure_jiffy_ + 1);
  const Scalar gain = Scalar(1) / std::fmin(averaged, mean_window_jiffies_);
  mean_rate_g_per_jiffy_ += gain * (observer_.rate_g_per_jiffy() - mean_rate_g_per_jiffy_);
}

template <typename Scalar>
void BasicModelCutoff<Scalar>::track_platform() {
  const auto ringing = model::platform_ringing(platform_hz_, kPlatformDamping<Scalar>, platform_kg_,
                                               observer_.static_g() / Scalar(1000));
  const Scalar impulse_s = last_impact_speed_m_s_ / kGravity<Scalar>;
  observer_.set_platform(ringing.omega_rad_s * jiffy_s_, ringing.damping_ratio, impulse_s / jiffy_s_);
}

template <typename Scalar>
Scalar BasicModelCutoff<Scalar>::observed_prediction_g() {
  const Scalar equilibrium_g = observer_.equilibrium_g();
  const Scalar per_g_per_jiffy = Scalar(1) / (Scalar(1000) * jiffy_s_);
  const auto prediction = model::predict_final(geometry_, equilibrium_g / Scalar(1000),
                                               observer_.rate_g_per_jiffy() * per_g_per_jiffy,
                                               mean_rate_g_per_jiffy_ * per_g_per_jiffy);
  growth_per_jiffy_g_ = observer_.rate_g_per_jiffy();
  estimates_.measured = true;
  estimates_.flow_kg_s = mean_rate_g_per_jiffy_ * per_g_per_jiffy;
  last_fall_time_s_ = prediction.fall_time_s;
  last_fall_height_m_ = prediction.fall_height_m;
  last_impact_speed_m_s_ = model::impact_speed(prediction.outflow_speed_m_s, kGravity<Scalar>, prediction.fall_height_m);
  return (equilibrium_g - start_weight_g_) + Scalar(1000) * prediction.above_reading_kg;
}

template <typename Scalar>
Scalar BasicModelCutoff<Scalar>::fitted_prediction_g() {
  const auto line = fit_.fit();
  const Scalar rate_kg_s = line.slope_per_sample / (Scalar(1000) * jiffy_s_);
  const auto prediction = model::predict_final(geometry_, line.value_at_newest / Scalar(1000), rate_kg_s);
  growth_per_jiffy_g_ = line.slope_per_sample;
  estimates_.measured = true;
  estimates_.flow_kg_s = rate_kg_s;
  last_fall_time_s_ = prediction.fall_time_s;
  last_fall_height_m_ = prediction.fall_height_m;
  return (line.value_at_newest - start_weight_g_) + Scalar(1000) * prediction.above_reading_kg;
}

// The first grains fall to the pile left by earlier fills, not to the floor.
template <typename Scalar>
Scalar BasicModelCutoff<Scalar>::first_fall_height_m() const {
  return geometry_.pile_grows ? fall_height_m(start_weight_g_) : geometry_.orifice_to_floor_m;
}

template <typename Scalar>
Scalar BasicModelCutoff<Scalar>::fall_height_m(Scalar net_weight_g) const {
  return model::fall_height_to_pile_m(geometry_.pile, geometry_.orifice_to_floor_m, net_weight_g / Scalar(1000));
}

template <typename Scalar>
Scalar BasicModelCutoff<Scalar>::settle_delay_s() const {
  // The let-through in seconds of full flow is shorter than the time it takes: a slow stroke lets the
  // last grains go late. Those fall from the orifice at almost no speed.
  return closing_duration_s_ + model::fall_time(Scalar(0), kGravity<Scalar>, last_fall_height_m_);
}

template class BasicModelCutoff<float>;
template class BasicModelCutoff<double>;

}  // namespace dynweigh::firmware
