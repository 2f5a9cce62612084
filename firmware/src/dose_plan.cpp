#include "dynweigh/firmware/dose_plan.hpp"

#include <cmath>

#include "dynweigh/model/fluctuation_average.hpp"
#include "dynweigh/model/oiml_r61_limits.hpp"

namespace dynweigh::firmware {
namespace {
// The rate's first jiffies after the stream is measured still carry the start-up: a fluctuation
// needs this many rates to be read at all.
constexpr std::uint32_t kLeastRates = 5;
constexpr float kAimedTopUpShare = 0.5f;
constexpr float kUndershootTopUpShare = 0.3f;
}  // namespace

const char* dose_plan_name(DosePlan plan) {
  switch (plan) {
    case DosePlan::full: return "full";
    case DosePlan::fine: return "fine";
    case DosePlan::topup: return "topup";
  }
  return "full";
}

float model_top_up_shortfall_g(DosePlan plan, float warn_low_g) {
  return (plan == DosePlan::topup ? kUndershootTopUpShare : kAimedTopUpShare) * warn_low_g;
}

void DosePlanner::configure(float class_x, float half_flow_ratio, float jiffy_s) {
  const float jiffy = jiffy_s > 0.0f ? jiffy_s : 0.01f;
  young_rates_ = std::uint32_t(std::lround(kYoungStreamS / jiffy));
  recent_gain_ = jiffy < kRecentRateS ? jiffy / kRecentRateS : 1.0f;
  class_x_ = class_x > 0.0f ? class_x : 1.0f;
  half_flow_ratio_ = half_flow_ratio > 0.0f && half_flow_ratio <= 1.0f ? half_flow_ratio : 0.5f;
}

void DosePlanner::start() {
  rates_ = 0;
  mean_ = 0.0f;
  m2_ = 0.0f;
  recent_ = 0.0f;
}

void DosePlanner::observe_rate(float rate_g_per_jiffy) {
  if (!std::isfinite(rate_g_per_jiffy)) return;
  ++rates_;
  const float delta = rate_g_per_jiffy - mean_;
  mean_ += delta / float(rates_);
  m2_ += delta * (rate_g_per_jiffy - mean_);
  recent_ = rates_ == 1 ? rate_g_per_jiffy : recent_ + recent_gain_ * (rate_g_per_jiffy - recent_);
}

float DosePlanner::fluctuation() const {
  if (rates_ < kLeastRates || !(mean_ > 0.0f)) return 0.0f;
  return std::sqrt(m2_ / float(rates_ - 1)) / mean_;
}

float DosePlanner::growth() const {
  if (rates_ < kLeastRates || rates_ >= young_rates_ || !(mean_ > 0.0f) || !(recent_ > mean_)) return 0.0f;
  return (recent_ - mean_) / mean_;
}

// The full close's stream would miss by enough to be worth a fine feed (its young stream's growth
// left out: that is gone by the close a fine-feed time later), and half open's stream fits the
// class. The scale the material's full-open closes showed holds their let-through too; the
// half-open close's own let-through is in its margin (fine_feed_choice).
bool DosePlanner::fine_feed_pays(float settled_stream_g, float stream_g, float limit_g) const {
  return kSigmas * settled_stream_g > kFineWorthLimits * limit_g && half_open_fits(stream_g, limit_g);
}

bool DosePlanner::half_open_fits(float stream_g, float limit_g) const {
  return kSigmas * stream_g * half_flow_ratio_ <= limit_g;
}

// Half open: less in flight by the flow's ratio, and the half-open stream measured again. Its close
// lets through half the flow for a closing time no fine-fed close confirms: the close aims short by
// what that adds beyond the class.
PlanChoice DosePlanner::fine_feed_choice(PlanChoice c, float stream_g, float scale, float full_flow_g_s) const {
  c.plan = DosePlan::fine;
  const float half_stream_g = scale * stream_g * half_flow_ratio_;
  const float let_through_g = kUnlearnedLetThroughS * half_flow_ratio_ * (full_flow_g_s > 0.0f ? full_flow_g_s : 0.0f);
  const float beyond_g =
      kSigmas * std::sqrt(half_stream_g * half_stream_g + let_through_g * let_through_g) - c.limit_g;
  c.margin_g = beyond_g > 0.0f ? beyond_g : 0.0f;
  return c;
}

float DosePlanner::class_limit_g(float target_g) const {
  return class_x_ * model::oiml_r61_x1_limits(target_g).initial_verification_g;
}

float DosePlanner::class_mean_limit_g(float target_g) const {
  return class_x_ * model::oiml_r61_x1_limits(target_g).in_service_g / 4.0f;
}

PlanChoice DosePlanner::choose(float target_g, float predicted_g, float in_flight_g, bool measuring, bool law_taught,
                               float flight_s, float let_through_sigma_g, float measured_sigma_scale,
                               FineFeedOutlook fine) const {
  PlanChoice c;
  c.limit_g = class_limit_g(target_g);
  const float in_flight = in_flight_g > 0.0f ? in_flight_g : 0.0f;
  // The flow's fluctuation is partly averaged out over the flight.
  const float kept = model::fluctuation_share_of_window_mean(kFluctuationCorrelationS, flight_s);
  const float measured_share = kept * fluctuation() + kEstimatorShare + growth();
  const float blind_share = law_taught ? kLearnedBlindShare : kBlindShare;
  const float stream_g = measured_share * in_flight;
  const float let_through_g = let_through_sigma_g > 0.0f ? let_through_sigma_g : 0.0f;
  const float scale = measured_sigma_scale > 0.0f ? measured_sigma_scale : 1.0f;
  c.sigma_g = measuring ? scale * std::sqrt(stream_g * stream_g + let_through_g * let_through_g)
                        : blind_share * (predicted_g > 0.0f ? predicted_g : 0.0f);
  if (kSigmas * c.sigma_g <= c.limit_g) return c;
  if (measuring && fine.every_dose && half_open_fits(stream_g, c.limit_g)) {
    c.plan = DosePlan::fine;
    return c;
  }
  const float settled_stream_g = scale * (kept * fluctuation() + kEstimatorShare) * in_flight;
  if (measuring && fine.in_reach && !fine.every_dose && fine_feed_pays(settled_stream_g, stream_g, c.limit_g)) {
    return fine_feed_choice(c, stream_g, scale, fine.full_flow_g_s);
  }
  c.plan = DosePlan::topup;
  c.margin_g = kSigmas * c.sigma_g - c.limit_g;
  return c;
}

}  // namespace dynweigh::firmware
