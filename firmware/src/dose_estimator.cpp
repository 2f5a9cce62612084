#include "dynweigh/firmware/dose_estimator.hpp"

#include <cmath>

#include "dynweigh/model/gravity.hpp"
#include "dynweigh/model/ideal_model.hpp"
#include "dynweigh/model/platform_frequency.hpp"

namespace dynweigh::firmware {
namespace {
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
// The first impact's sample holds a part-jiffy of landing: a few samples more tell S from k L.
constexpr std::uint32_t kObserverSettleJiffies = 3;
}  // namespace

template <typename Scalar>
void BasicDoseEstimator<Scalar>::configure(const Parameters& p, Scalar prior_rate_kg_s,
                                           const model::CutoffGeometry<Scalar>& full_open) {
  const auto get = [&p](ParameterId id) { return Scalar(p.get(id)); };
  full_open_ = full_open;
  jiffy_s_ = get(ParameterId::jiffy_ms) / Scalar(1000);
  prior_rate_kg_s_ = prior_rate_kg_s;
  prior_per_jiffy_g_ = Scalar(1000) * prior_rate_kg_s_ * jiffy_s_;
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
  auto tuning = observer_.tuning();
  tuning.rate_walk_g = kRateWalkPerJiffy<Scalar> * prior_per_jiffy_g_;
  tuning.landing_scatter_g = kLandingScatter<Scalar> * prior_per_jiffy_g_;
  observer_.set_tuning(tuning);
  mean_window_jiffies_ = std::fmax(Scalar(1), get(ParameterId::model_window_ms) / get(ParameterId::jiffy_ms));
}

template <typename Scalar>
void BasicDoseEstimator<Scalar>::start(Scalar start_weight_g, const DoseValveTiming<Scalar>& timing) {
  start_weight_g_ = start_weight_g;
  opening_delay_s_ = timing.opening_delay_s;
  ramp_delay_s_ = timing.ramp_delay_s;
  // The first grains land a stroke before the whole stream does.
  established_jiffies_ = std::uint32_t(std::ceil(timing.stroke_s / jiffy_s_)) + kObserverSettleJiffies;
  jiffies_ = 0;
  impacted_ = false;
  half_stream_ = false;
  fit_.reset();
  observer_.stop();
  opening_.start(start_weight_g, jiffy_s_, kSampleNoiseG<Scalar>);
  estimates_ = DoseEstimates<Scalar>{};
  stream_confirmed_ = false;
  previous_sample_g_ = start_weight_g;
  rate_change_pending_ = false;
}

// The first impact, timed within the jiffy, tells an installer (the console's `estimates`) whether
// the valve's timing typed in agrees with what the scale sees.
template <typename Scalar>
void BasicDoseEstimator<Scalar>::time_opening(Scalar net_weight_g) {
  ++jiffies_;
  if (estimates_.impact_timed) return;
  // The sample of the n-th jiffy is the opening estimator's sample n - 1 (0 at the command).
  opening_.observe(net_weight_g);
  if (!opening_.impact_found()) return;
  estimates_.impact_timed = true;
  estimates_.first_impact_s = opening_.first_impact_s();
  estimates_.dead_time_s = opening_.dead_time_s(first_fall_height_m(), model::kGravity<Scalar>);
}

// Once the stream has run a while, the impulse its impact brings, against the geometry typed in.
template <typename Scalar>
bool BasicDoseEstimator<Scalar>::confirm_stream() {
  if (!use_observer_ || !estimates_.impact_timed || stream_confirmed_ || !measuring() || half_stream_) return false;
  if (jiffies_ < measure_jiffy_ + kSignatureJiffies) return false;
  // No stream worth the name (a scale that does not see the flow, as in the hourglass): nothing to
  // read an impulse from, and the "first impact" was something else, not a lesson about the valve.
  if (!(mean_rate_g_per_jiffy_ > kSignatureMinimumFlow<Scalar> * prior_per_jiffy_g_)) return false;
  stream_confirmed_ = true;
  const model::ImpactObservation<Scalar> seen{
      observer_.equilibrium_g() - start_weight_g_,
      Scalar(jiffies_ - 1) * jiffy_s_, mean_rate_g_per_jiffy_ / (Scalar(1000) * jiffy_s_),
      model::landing_start_s(estimates_.first_impact_s, ramp_delay_s_)};
  estimates_.signature = model::impact_signature(seen, full_open_.bore_area_m2, full_open_.bulk_density, model::kGravity<Scalar>);
  return true;
}

template <typename Scalar>
void BasicDoseEstimator<Scalar>::track_flow(Scalar net_weight_g, Scalar impact_speed_m_s) {
  const Scalar previous_g = previous_sample_g_;
  previous_sample_g_ = net_weight_g;
  const bool first_impact = !impacted_ && net_weight_g - start_weight_g_ >= impact_threshold_g_;
  if (first_impact) {
    impacted_ = true;
    impact_jiffy_ = jiffies_;
  }
  if (!use_observer_) {
    if (impacted_ && jiffies_ > impact_jiffy_ + settle_jiffies_) fit_.push(net_weight_g);
  } else if (first_impact) {
    start_observer(net_weight_g, previous_g);
  } else if (observer_.started()) {
    if (rate_change_pending_ && jiffies_ >= impact_jiffy_) {
      observer_.expect_rate_change(expected_rate_g_per_jiffy_);
      rate_change_pending_ = false;
    }
    track_platform(impact_speed_m_s);
    observer_.observe(net_weight_g);
    average_rate();
  }
  if (measuring()) record_flow();
}

// The jump is the stream's momentum; what has come to rest is the part of a jiffy since the first
// grains landed, which the valve's timing and the fall from rest tell best. A few grams of error
// there would otherwise read as k times less rate.
template <typename Scalar>
void BasicDoseEstimator<Scalar>::start_observer(Scalar net_weight_g, Scalar previous_g) {
  const Scalar prior_per_jiffy = prior_per_jiffy_g_;
  const Scalar prior_v0 = model::outflow_speed(prior_rate_kg_s_, full_open_.bore_area_m2, full_open_.bulk_density);
  const Scalar fall_s = model::fall_time(prior_v0, model::kGravity<Scalar>, first_fall_height_m());
  const Scalar landed_s = Scalar(jiffies_ - 1) * jiffy_s_ - (opening_delay_s_ + fall_s);
  const Scalar landed_jiffies = std::fmin(std::fmax(landed_s / jiffy_s_, Scalar(0)), Scalar(1));
  observer_.start(net_weight_g, previous_g, start_weight_g_ + landed_jiffies * prior_per_jiffy, prior_per_jiffy,
                  Scalar(0.5) * prior_per_jiffy, prior_per_jiffy);
  measure_jiffy_ = jiffies_ + established_jiffies_;
}

// The first grains fall to the pile left by earlier fills, not to the floor.
template <typename Scalar>
Scalar BasicDoseEstimator<Scalar>::first_fall_height_m() const {
  return full_open_.pile_grows
             ? model::fall_height_to_pile_m(full_open_.pile, full_open_.orifice_to_floor_m, start_weight_g_ / Scalar(1000))
             : full_open_.orifice_to_floor_m;
}

template <typename Scalar>
void BasicDoseEstimator<Scalar>::track_platform(Scalar impact_speed_m_s) {
  const auto ringing = model::platform_ringing(platform_hz_, kPlatformDamping<Scalar>, platform_kg_,
                                               observer_.static_g() / Scalar(1000));
  const Scalar impulse_s = impact_speed_m_s / model::kGravity<Scalar>;
  observer_.set_platform(ringing.omega_rad_s * jiffy_s_, ringing.damping_ratio, impulse_s / jiffy_s_);
}

// The mean of the observed rate since the stream was whole (first impact, or the fine feed's
// landing), then a running mean over `model_window_ms`.
template <typename Scalar>
void BasicDoseEstimator<Scalar>::average_rate() {
  if (jiffies_ < measure_jiffy_) return;
  const Scalar averaged = Scalar(jiffies_ - measure_jiffy_ + 1);
  const Scalar gain = Scalar(1) / std::fmin(averaged, mean_window_jiffies_);
  mean_rate_g_per_jiffy_ += gain * (observer_.rate_g_per_jiffy() - mean_rate_g_per_jiffy_);
}

// The flow reported is the full-open stream's: a fine feed's half-open stream is the valve's, not
// the material's. The line fit goes on either way (the line estimator predicts from it).
template <typename Scalar>
void BasicDoseEstimator<Scalar>::record_flow() {
  estimates_.measured = true;
  Scalar flow_kg_s;
  if (use_observer_) {
    flow_kg_s = mean_rate_g_per_jiffy_ / (Scalar(1000) * jiffy_s_);
  } else {
    line_ = fit_.fit();
    flow_kg_s = line_.slope_per_sample / (Scalar(1000) * jiffy_s_);
  }
  if (!half_stream_) estimates_.flow_kg_s = flow_kg_s;
}

template <typename Scalar>
void BasicDoseEstimator<Scalar>::expect_half_stream(Scalar landing_s, Scalar half_rate_g_per_jiffy) {
  half_stream_ = true;
  fit_.reset();
  // Fitting starts after the half-open stream has landed and the impact has settled, as at the
  // first impact.
  impact_jiffy_ = jiffies_ + std::uint32_t(std::ceil(landing_s / jiffy_s_));
  measure_jiffy_ = impact_jiffy_ + established_jiffies_;
  expected_rate_g_per_jiffy_ = half_rate_g_per_jiffy;
  rate_change_pending_ = true;
}

template class BasicDoseEstimator<float>;
template class BasicDoseEstimator<double>;

}  // namespace dynweigh::firmware
