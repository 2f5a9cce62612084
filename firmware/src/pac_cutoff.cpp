#include "dynweigh/firmware/pac_cutoff.hpp"

namespace dynweigh::firmware {
namespace {
// The prior's uncertainty: K1 within half itself; K2 such that its term may reach half the spill at
// the prior flow. One fill's spill scatters by a few grams plus 2 % of itself (the flow's
// fluctuation over the closing, the valve's jitter). Forgetting 0.9: the last ten fills count.
constexpr float kK1Uncertainty = 0.5f;
constexpr float kK2Uncertainty = 0.5f;
constexpr float kNoiseBaseG = 2.0f;
constexpr float kNoiseShare = 0.02f;
constexpr float kForgetting = 0.9f;
}  // namespace

void PacCutoff::configure(const Parameters& p) {
  fill_.configure(p);
  prior_k1_ = 1000.0f * prior_spill_lag_s(p);  // grams per kg/s
  prior_flow_kg_s_ = fill_.blind().prior_flow_kg_s();
  reset_to_prior();
}

void PacCutoff::reset_to_prior() {
  spill_.configure(kForgetting, kNoiseBaseG + kNoiseShare * prior_k1_ * prior_flow_kg_s_);
  const float k1_sd = kK1Uncertainty * prior_k1_ + 1.0f;
  spill_.reset(prior_k1_, 0.0f, k1_sd, kK2Uncertainty * k1_sd / prior_flow_kg_s_);
}

void PacCutoff::restore(const PacLearned& learned) {
  reset_to_prior();
  if (learned.spill.fills > 0) spill_.restore(learned.spill);
  fill_.blind().restore(learned.blind);
}

CloseDecision PacCutoff::step(float filled_g) {
  return fill_.step(filled_g, [this](float flow_kg_s) { return spill_g(flow_kg_s); });
}

void PacCutoff::learn(float final_g) {
  const FlowBaselineFill::AtClose& c = fill_.at_close();
  if (c.measured) spill_.update(c.flow_kg_s, c.flow_kg_s * c.flow_kg_s, final_g - c.reading_g);
  fill_.learn_blind(final_g);
}

}  // namespace dynweigh::firmware
