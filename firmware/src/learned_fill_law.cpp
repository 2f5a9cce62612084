#include "dynweigh/firmware/learned_fill_law.hpp"

#include <cmath>

namespace dynweigh::firmware {
namespace {
// The prior's uncertainty: the flow within half itself (a density guessed up to 40 % off, the
// Beverloo constants), the lag within 0.05 s (the valve's dead time, stroke and the flow's start-up);
// one fill's scatter about the law, 10 ms of flow (the valve's jitter, the flow's fluctuation).
constexpr float kFlowUncertainty = 0.7f;
constexpr float kLagUncertaintyS = 0.05f;
constexpr float kNoiseS = 0.01f;
constexpr float kForgetting = 0.9f;
// A learned flow outside this band about the prior is no flow this bore gives: the fill was not a
// lesson (a silo run low, a blocked valve) and the law goes back to what it was.
constexpr float kLowestFlowShare = 0.25f;
constexpr float kHighestFlowShare = 4.0f;
// A measured close is off by at most the let-through of a valve that is 0.25 s off its datasheet;
// after the first, a fill moves the learned let-through by a share of its residual only.
constexpr float kResidualLimitS = 0.25f;
constexpr float kResidualMemory = 3.0f;
constexpr float kRefinementStepS = 0.02f;
// The let-through learned is used once it is clearly off the timing in use: by more than the
// scatter that a mean of a few fills keeps (a flow fluctuating 3 %: ~5 ms).
constexpr float kLetThroughDeadbandS = 0.01f;
// No dose is open for an hour.
constexpr float kLongestOpenS = 3600.0f;
// No valve lets a second of its flow through.
constexpr float kLetThroughLimitS = 1.0f;
}  // namespace

void LearnedFillLaw::configure(float prior_flow_g_s, float prior_lag_s) {
  prior_flow_g_s_ = prior_flow_g_s;
  prior_lag_s_ = prior_lag_s;
  law_.configure(kForgetting, kNoiseS * prior_flow_g_s);
  law_.reset(prior_flow_g_s, -prior_flow_g_s * prior_lag_s, kFlowUncertainty * prior_flow_g_s,
             kLagUncertaintyS * prior_flow_g_s);
  learned_ = MaterialLearning{};
  learned_.open_time_law = law_.state();
  learned_.open_time_law.fills = 0;
}

void LearnedFillLaw::restore(const MaterialLearning& learned) {
  configure(prior_flow_g_s_, prior_lag_s_);
  if (learned.open_time_law.fills > 0 && law_.restore(learned.open_time_law)) {
    learned_.open_time_law = learned.open_time_law;
  }
  if (learned_.open_time_law.fills > 0 && learned.law_longest_open_s > 0.0f &&
      learned.law_longest_open_s < kLongestOpenS) {
    learned_.law_longest_open_s = learned.law_longest_open_s;
  }
  learned_.doses = learned.doses;
  learned_.measured_closes = learned.measured_closes;
  if (learned.residual_fills > 0 && std::fabs(learned.close_let_through_s) <= kLetThroughLimitS) {
    learned_.close_let_through_s = learned.close_let_through_s;
    learned_.residual_fills = learned.residual_fills;
  }
}

float LearnedFillLaw::open_s_for(float final_g) const {
  const TwoParameterRls::State& s = law_.state();
  const float open_s = s.theta1 > 0.0f ? (final_g - s.theta2) / s.theta1 : 0.0f;
  return open_s > 0.0f && std::isfinite(open_s) ? open_s : 0.0f;
}

// Within the deadband the timing in use stands: what is learned then is the scatter of the fills.
float LearnedFillLaw::close_residual_s(float let_through_in_use_s) const {
  const float off_s = learned_.close_let_through_s - let_through_in_use_s;
  return learned_.residual_fills > 0 && std::fabs(off_s) > kLetThroughDeadbandS ? off_s : 0.0f;
}

void LearnedFillLaw::learn(const CloseRecord& close, float final_g, float close_sigma_g) {
  if (!close.valid || !close.from_full_open || !(final_g > 0.0f) || !(close.open_s > 0.0f)) return;
  learn_open_time(close.open_s, final_g);
  learned_.doses.add(close.open_s, final_g);
  if (!close.measured || !(close.flow_g_s > 0.0f)) return;
  if (close_sigma_g > 0.0f) learned_.measured_closes.add((final_g - close.prediction_g) / close_sigma_g);
  const float residual_s = (final_g - close.prediction_g) / close.flow_g_s;
  learn_let_through(close.let_through_s + std::fmax(-kResidualLimitS, std::fmin(kResidualLimitS, residual_s)));
}

void LearnedFillLaw::learn_open_time(float open_s, float final_g) {
  const TwoParameterRls::State before = law_.state();
  if (!law_.update(open_s, 1.0f, final_g)) return;
  const float share = law_.state().theta1 / prior_flow_g_s_;
  if (!(share >= kLowestFlowShare && share <= kHighestFlowShare)) {
    law_.restore(before);
    extend_reach_if_short(open_s, final_g);
    return;
  }
  learned_.open_time_law = law_.state();
  learned_.law_longest_open_s = std::fmax(learned_.law_longest_open_s, open_s);
}

// A fill the law does not take (its line would have a flow no bore gives: on a slow valve and a
// slow start-up the first few tenths of a second deliver far less than in proportion) still shows
// how far the law may reach, if it delivered no more than the law said: a close the law times up to
// there ends short, and a top-up finishes it. Without this the reach stays where the last lesson
// left it, every dose closes there, and one that must close far later never gets the chance.
void LearnedFillLaw::extend_reach_if_short(float open_s, float final_g) {
  if (learned_.open_time_law.fills == 0 || final_g > law_.predict(open_s, 1.0f)) return;
  learned_.law_longest_open_s = std::fmax(learned_.law_longest_open_s, open_s);
}

// What this close showed the valve to let through (the let-through its prediction used, and what the
// final came out above it) joins the mean of the last few: the first measured close corrects the
// datasheet's whole, later ones refine it, each by a bounded step, so that one disturbed fill cannot
// carry the next ones off.
void LearnedFillLaw::learn_let_through(float shown_s) {
  const bool first = learned_.residual_fills == 0;
  const float before = first ? shown_s : learned_.close_let_through_s;
  const float n = float(learned_.residual_fills) + 1.0f;
  const float step = (shown_s - before) / std::fmin(n, kResidualMemory);
  const float after = before + std::fmax(-kRefinementStepS, std::fmin(kRefinementStepS, step));
  if (!(std::fabs(after) <= kLetThroughLimitS)) return;
  learned_.close_let_through_s = after;
  if (learned_.residual_fills < 0xFFFF) ++learned_.residual_fills;
}

}  // namespace dynweigh::firmware
