#include "dynweigh/firmware/model_cutoff.hpp"

#include <cmath>

#include "dynweigh/model/bore_area.hpp"
#include "dynweigh/model/valve_let_through.hpp"

namespace dynweigh::firmware {
namespace {
constexpr float kGravity = 9.81f;
// The material is unknown until it flows: Beverloo's constants for a typical free-flowing sand
// (shared/PHYSICS.md §3) give the prior; the measured flow replaces it after the first impact.
constexpr model::BeverlooMaterial<float> prior_material(float bulk_density) {
  return {0.58f, 1.5f, 0.0005f, bulk_density};
}
}  // namespace

void ModelCutoff::configure(const Parameters& p) {
  jiffy_s_ = p.get(ParameterId::jiffy_ms) / 1000.0f;
  const float bore_m = p.get(ParameterId::bore_mm) / 1000.0f;
  const float density = p.get(ParameterId::density);
  const float dead_s = p.get(ParameterId::valve_dead_ms) / 1000.0f;
  const float stroke_s = p.get(ParameterId::valve_stroke_ms) / 1000.0f;
  const auto material = prior_material(density);

  geometry_.g = kGravity;
  geometry_.bore_area_m2 = model::bore_area_m2(bore_m);
  geometry_.bulk_density = density;
  geometry_.orifice_to_floor_m = p.get(ParameterId::fall_mm) / 1000.0f;
  geometry_.pile.container_diameter_m = p.get(ParameterId::container_mm) / 1000.0f;
  geometry_.pile.repose_angle_rad = p.get(ParameterId::repose_deg) * float(M_PI) / 180.0f;
  geometry_.pile.bulk_density = density;
  geometry_.pile_grows = true;
  geometry_.closing_flow_seconds = model::closing_flow_seconds(material, kGravity, bore_m, dead_s, stroke_s);
  full_area_m2_ = geometry_.bore_area_m2;
  full_closing_flow_s_ = geometry_.closing_flow_seconds;
  const float full_rate = model::discharge_at_stroke_kg_s(material, kGravity, bore_m, 1.0f);
  const float half_rate = model::discharge_at_stroke_kg_s(material, kGravity, bore_m, 0.5f);
  half_flow_ratio_ = full_rate > 0.0f ? half_rate / full_rate : 0.5f;
  half_closing_flow_s_ = half_rate > 0.0f ? model::closing_flow_seconds(material, kGravity, bore_m, dead_s, stroke_s, 0.5f) *
                                                full_rate / half_rate
                                          : dead_s;
  half_transition_s_ = dead_s + 0.25f * stroke_s;

  prior_rate_kg_s_ = model::beverloo_discharge_kg_s(material, kGravity, bore_m);
  // Opening mirrors closing: the flow that is missing at the start equals the let-through at the end.
  opening_delay_s_ = dead_s + stroke_s - (geometry_.closing_flow_seconds - dead_s);
  settle_jiffies_ = std::uint32_t(p.get(ParameterId::impact_settle_ms) / p.get(ParameterId::jiffy_ms));
  fit_.set_window(std::size_t(p.get(ParameterId::model_window_ms) / p.get(ParameterId::jiffy_ms)));
  // 20 d, or what the prior flow brings in two jiffies if that is more: a clear sign of flow.
  impact_threshold_g_ = std::fmax(20.0f, 2000.0f * prior_rate_kg_s_ * jiffy_s_);
}

void ModelCutoff::start(float start_weight_g) {
  start_weight_g_ = start_weight_g;
  jiffies_ = 0;
  impacted_ = false;
  fine_ = false;
  geometry_.bore_area_m2 = full_area_m2_;
  geometry_.closing_flow_seconds = full_closing_flow_s_;
  fit_.reset();
  growth_per_jiffy_g_ = prior_rate_kg_s_ * 1000.0f * jiffy_s_;
  last_fall_time_s_ = model::fall_time(0.0f, kGravity, geometry_.orifice_to_floor_m);
}

void ModelCutoff::switch_to_half(float predicted_now_g) {
  fine_ = true;
  predicted_at_switch_g_ = predicted_now_g;
  measured_full_rate_g_per_jiffy_ = growth_per_jiffy_g_;
  switch_jiffy_ = jiffies_;
  geometry_.bore_area_m2 = full_area_m2_ * model::open_area_fraction(0.5f);
  geometry_.closing_flow_seconds = half_closing_flow_s_;
  growth_per_jiffy_g_ *= half_flow_ratio_;
  fit_.reset();
  // The half-open stream lands a fall time after the valve has moved; fitting starts after that
  // and the impact's settling, like at the first impact.
  impact_jiffy_ = jiffies_ + std::uint32_t(std::ceil((half_transition_s_ + last_fall_time_s_) / jiffy_s_));
}

float ModelCutoff::prior_prediction_g() const {
  if (fine_) {
    const float since_switch = float(jiffies_ - switch_jiffy_);
    return predicted_at_switch_g_ + since_switch * measured_full_rate_g_per_jiffy_ * half_flow_ratio_;
  }
  // The sample of the n-th jiffy shows n - 1 jiffies of the valve's being open.
  const float open_s = float(jiffies_ - 1) * jiffy_s_;
  const float flowing_s = std::fmax(0.0f, open_s - opening_delay_s_);
  return 1000.0f * prior_rate_kg_s_ * (flowing_s + geometry_.closing_flow_seconds);
}

float ModelCutoff::observe(float net_weight_g) {
  ++jiffies_;
  if (!impacted_ && net_weight_g - start_weight_g_ >= impact_threshold_g_) {
    impacted_ = true;
    impact_jiffy_ = jiffies_;
  }
  if (impacted_ && jiffies_ > impact_jiffy_ + settle_jiffies_) fit_.push(net_weight_g);
  if (!measuring()) return prior_prediction_g();

  const auto line = fit_.fit();
  const float rate_kg_s = line.slope_per_sample / (1000.0f * jiffy_s_);
  const auto prediction = model::predict_final(geometry_, line.value_at_newest / 1000.0f, rate_kg_s);
  growth_per_jiffy_g_ = line.slope_per_sample;
  last_fall_time_s_ = prediction.fall_time_s;
  return 1000.0f * prediction.final_kg - start_weight_g_;
}

float ModelCutoff::fall_height_m(float net_weight_g) const {
  return model::fall_height_to_pile_m(geometry_.pile, geometry_.orifice_to_floor_m, net_weight_g / 1000.0f);
}

float ModelCutoff::settle_delay_s() const {
  return geometry_.closing_flow_seconds + last_fall_time_s_;
}

}  // namespace dynweigh::firmware
