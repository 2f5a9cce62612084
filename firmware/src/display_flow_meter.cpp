#include "dynweigh/firmware/display_flow_meter.hpp"

#include <cmath>

namespace dynweigh::firmware {
namespace {
// A clear sign that the stream has landed: 20 d above the start.
constexpr float kLandingG = 20.0f;
// The window: at least a quarter second and three periods of the platform's ringing before the flow
// counts as measured; then it grows to a second. The stream's landing rate wanders about its mean
// within a fraction of a second and the display's slope over a short window with it (and with the
// pile's answer to it), while the spill follows the mean: a second of it predicts the spill best.
constexpr float kMinimumWindowS = 0.25f;
constexpr float kWindowPeriods = 3.0f;
constexpr float kLongestWindowS = 1.0f;
// The critically damped IIR's step response has a derivative of (t / tau^2) e^(-t / tau): after
// 8 tau the impact's step (about the flow times the fall time) still adds under 2 % to the slope.
constexpr float kIirSettleTaus = 8.0f;
// The moving average passes a step in one window; the impact's own relaxation and the first grains'
// scatter take a little longer.
constexpr float kAverageMarginS = 0.1f;
}  // namespace

void DisplayFlowMeter::configure(const Parameters& p) {
  jiffy_s_ = p.get(ParameterId::jiffy_ms) / 1000.0f;
  landing_g_ = kLandingG;
  const float corner_hz = p.get(ParameterId::filter_hz);
  float settle_s = kAverageMarginS;
  switch (p.filter()) {
    case FilterKind::iir: settle_s = kIirSettleTaus / (2.0f * float(M_PI) * corner_hz); break;
    case FilterKind::average: settle_s = 0.5f / corner_hz + kAverageMarginS; break;
    case FilterKind::none: break;
  }
  const float stroke_s = p.get(ParameterId::valve_stroke_ms) / 1000.0f;
  blank_jiffies_ = std::uint32_t(std::ceil((stroke_s + settle_s) / jiffy_s_));
  const float platform_hz = p.get(ParameterId::platform_hz);
  float window_s = kMinimumWindowS;
  if (platform_hz > 0.0f && kWindowPeriods / platform_hz > window_s) window_s = kWindowPeriods / platform_hz;
  const std::uint32_t window = std::uint32_t(std::lround(window_s / jiffy_s_));
  window_jiffies_ = window < 2 ? 2 : (window > kHistory - 1 ? kHistory - 1 : window);
  const std::uint32_t longest = std::uint32_t(std::lround(kLongestWindowS / jiffy_s_));
  longest_window_jiffies_ = longest < window_jiffies_ ? window_jiffies_ : (longest > kHistory - 1 ? kHistory - 1 : longest);
}

void DisplayFlowMeter::start() {
  for (float& h : history_) h = 0.0f;
  jiffies_ = 0;
  landing_jiffy_ = 0;
  landed_ = false;
  measured_ = false;
  flow_kg_s_ = 0.0f;
}

void DisplayFlowMeter::push(float filled_g) {
  history_[jiffies_ % kHistory] = filled_g;
  ++jiffies_;
  if (!landed_ && filled_g >= landing_g_) {
    landed_ = true;
    landing_jiffy_ = jiffies_;
  }
  if (!landed_ || jiffies_ - landing_jiffy_ < blank_jiffies_ + window_jiffies_) return;
  std::uint32_t span = jiffies_ - landing_jiffy_ - blank_jiffies_;
  if (span > longest_window_jiffies_) span = longest_window_jiffies_;
  const float now = history_[(jiffies_ - 1) % kHistory];
  const float then = history_[(jiffies_ - 1 - span) % kHistory];
  const float rate = (now - then) / (float(span) * jiffy_s_ * 1000.0f);
  flow_kg_s_ = rate > 0.0f ? rate : 0.0f;
  measured_ = true;
}

}  // namespace dynweigh::firmware
