#include "dynweigh/firmware/blind_close.hpp"

#include "dynweigh/model/beverloo.hpp"

namespace dynweigh::firmware {
namespace {
// Beverloo's constants for a typical free-flowing sand, as the model strategy's prior.
constexpr float kPriorC = 0.58f;
constexpr float kPriorK = 1.5f;
constexpr float kPriorGrainM = 0.0005f;
constexpr float kGravity = 9.81f;
// The first fill's flow: 20 % above the prior, so a density guessed high by up to that closes early.
constexpr float kConservative = 1.2f;
// The prior's uncertainty: the flow within half itself (density, material), the loss within 0.1 s of
// it; one fill's scatter about the law, 10 ms of flow (the valve's jitter, the flow's fluctuation).
constexpr float kFlowUncertainty = 0.5f;
constexpr float kLossUncertaintyS = 0.1f;
constexpr float kNoiseS = 0.01f;
constexpr float kForgetting = 0.9f;
// A learned flow below this share of the prior is no law to time a fill by.
constexpr float kMinimumFlowShare = 0.05f;
// A bore Beverloo says arches over still gets a prior to time by (the flow is then learned).
constexpr float kMinimumPriorKgS = 0.01f;
constexpr float kSmallestOpening = 0.25f;  // of the stroke
}  // namespace

void BlindClose::configure(const Parameters& p) {
  const model::BeverlooMaterial<float> material{kPriorC, kPriorK, kPriorGrainM, p.get(ParameterId::density)};
  const float flow = model::beverloo_discharge_kg_s(material, kGravity, p.get(ParameterId::bore_mm) / 1000.0f);
  prior_flow_kg_s_ = flow > kMinimumPriorKgS ? flow : kMinimumPriorKgS;
  // A close that acts before the valve has opened a quarter of its stroke lets next to nothing through
  // (a fill the cycle must take for an empty silo): the valve's smallest dose is timed at that.
  earliest_s_ = p.get(ParameterId::valve_dead_ms) / 1000.0f + kSmallestOpening * p.get(ParameterId::valve_stroke_ms) / 1000.0f;
  reset_to_prior();
}

void BlindClose::reset_to_prior() {
  const float flow_g_s = 1000.0f * kConservative * prior_flow_kg_s_;
  law_.configure(kForgetting, kNoiseS * flow_g_s);
  law_.reset(flow_g_s, 0.0f, kFlowUncertainty * flow_g_s, kLossUncertaintyS * flow_g_s);
}

void BlindClose::restore(const TwoParameterRls::State& learned) {
  reset_to_prior();
  if (learned.fills > 0) law_.restore(learned);
}

float BlindClose::close_time_s(float target_g) const {
  const TwoParameterRls::State& s = law_.state();
  const float floor_g_s = kMinimumFlowShare * 1000.0f * prior_flow_kg_s_;
  const float flow_g_s = s.theta1 > floor_g_s ? s.theta1 : floor_g_s;
  const float t = (target_g - s.theta2) / flow_g_s;
  return t > earliest_s_ ? t : earliest_s_;
}

void BlindClose::learn(float close_s, float final_g) { law_.update(close_s, 1.0f, final_g); }

}  // namespace dynweigh::firmware
