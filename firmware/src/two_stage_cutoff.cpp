#include "dynweigh/firmware/two_stage_cutoff.hpp"

namespace dynweigh::firmware {
namespace {
// The coarse rate: the reading's rise over the last quarter second (several periods of the
// platform's ringing, which the display filter leaves a trace of).
constexpr std::uint32_t kCoarseRateJiffies = 25;
// The reduced stream has landed when the reading rises at less than half the coarse rate over a
// tenth of a second: a half-open stream is less than half the full one, and the impulse it no longer
// brings makes the reading dip through the display filter.
constexpr std::uint32_t kDipJiffies = 10;
constexpr float kDipFraction = 0.5f;
// A stream that never shows its dip (a half-open flow close to the full, or a valve stuck open) is
// armed after this long, or once the reading has risen twice the learned overrun since the switch:
// the dip's impulse is less than the overrun itself, so a healthy fine feed never gets that far.
constexpr float kBlankLimitS = 3.0f;
constexpr float kBlankLimitOverruns = 2.0f;
// Less than this coarse rate is no coarse stream: nothing has landed yet to wait out.
constexpr float kNoStreamG_S = 20.0f;
// The adaptation, as SIWAREX and Rice Lake's PREACT LEARN: half the last error, capped, so one odd
// fill cannot throw the preact far; the coarse overrun takes half of each new measurement.
constexpr float kLearnGain = 0.5f;
constexpr float kCapBaseG = 10.0f;
constexpr float kCapFraction = 0.25f;

float magnitude(float x) { return x < 0.0f ? -x : x; }
}  // namespace

void TwoStageCutoff::configure(const Parameters& p) {
  jiffy_s_ = p.get(ParameterId::jiffy_ms) / 1000.0f;
  band_g_ = p.get(ParameterId::twostage_band_g);
  fine_preact_g_ = p.get(ParameterId::twostage_preact_g);
  coarse_g_ = p.get(ParameterId::twostage_coarse_g);
  // The display filter's settling after the dip: six time constants of the critically damped IIR
  // (2 % of a step left), a whole window of the moving average, a few jiffies unfiltered.
  const float corner_hz = p.get(ParameterId::filter_hz);
  switch (p.filter()) {
    case FilterKind::iir: settle_s_ = 1.0f / corner_hz; break;
    case FilterKind::average: settle_s_ = 0.5f / corner_hz + 0.05f; break;
    case FilterKind::none: settle_s_ = 0.05f; break;
  }
}

void TwoStageCutoff::start(float target_g) {
  for (float& h : history_) h = 0.0f;
  jiffies_ = 0;
  stage_ = Stage::coarse;
  target_g_ = target_g;
  prediction_g_ = 0.0f;
  coarse_rate_g_s_ = 0.0f;
  dipped_ = false;
  measured_overrun_ = false;
}

float TwoStageCutoff::slope_g_s(std::uint32_t span) const {
  if (span > jiffies_ - 1) span = jiffies_ - 1;
  if (span == 0) return 0.0f;
  const float now = history_[(jiffies_ - 1) % kHistory];
  const float then = history_[(jiffies_ - 1 - span) % kHistory];
  return (now - then) / (float(span) * jiffy_s_);
}

ValveCommand TwoStageCutoff::step(float filled_g) {
  history_[jiffies_ % kHistory] = filled_g;
  ++jiffies_;
  prediction_g_ = filled_g;
  if (stage_ == Stage::coarse) {
    const float rate = slope_g_s(kCoarseRateJiffies);
    coarse_rate_g_s_ = rate > 0.0f ? rate : 0.0f;
    if (filled_g + coarse_g_ < target_g_ - fine_preact_g_ - band_g_) return ValveCommand::open;
    switch_to_fine(filled_g);
  }
  if (stage_ == Stage::fine_blanked) {
    if (!fine_stream_settled(filled_g)) return ValveCommand::half;
    stage_ = Stage::fine;
  }
  if (stage_ == Stage::fine) {
    prediction_g_ = filled_g + fine_preact_g_;
    if (prediction_g_ < target_g_) return ValveCommand::half;
    stage_ = Stage::closed;
  }
  return ValveCommand::closed;
}

void TwoStageCutoff::switch_to_fine(float filled_g) {
  switch_weight_g_ = filled_g;
  switch_jiffy_ = jiffies_;
  // Switched before any coarse stream landed: there is no overrun to wait out.
  stage_ = coarse_rate_g_s_ < kNoStreamG_S ? Stage::fine : Stage::fine_blanked;
}

bool TwoStageCutoff::fine_stream_settled(float filled_g) {
  const float since_switch_s = float(jiffies_ - switch_jiffy_) * jiffy_s_;
  if (!dipped_ && slope_g_s(kDipJiffies) < kDipFraction * coarse_rate_g_s_) {
    dipped_ = true;
    dip_jiffy_ = jiffies_;
  }
  if (dipped_ && float(jiffies_ - dip_jiffy_) * jiffy_s_ >= settle_s_) {
    // What the reading rose from the switch to here: where the next fill must switch for its settled
    // fine feed to begin `band` before the fine cutoff.
    overrun_g_ = filled_g - switch_weight_g_;
    measured_overrun_ = true;
    return true;
  }
  return since_switch_s >= kBlankLimitS || filled_g - switch_weight_g_ >= kBlankLimitOverruns * coarse_g_;
}

void TwoStageCutoff::learn(float final_g) {
  const float error = final_g - target_g_;
  const float cap = kCapBaseG + kCapFraction * magnitude(fine_preact_g_);
  float step = kLearnGain * error;
  step = step > cap ? cap : (step < -cap ? -cap : step);
  fine_preact_g_ += step;
  if (measured_overrun_) {
    coarse_g_ += kLearnGain * (overrun_g_ - coarse_g_);
    coarse_g_ = coarse_g_ < 0.0f ? 0.0f : coarse_g_;
  }
}

}  // namespace dynweigh::firmware
