#include "dynweigh/firmware/flow_baseline_fill.hpp"

#include <cmath>

namespace dynweigh::firmware {
namespace {
constexpr float kConservative = 1.2f;
}

float prior_spill_lag_s(const Parameters& p) {
  const float dead_s = p.get(ParameterId::valve_dead_ms) / 1000.0f;
  const float stroke_s = p.get(ParameterId::valve_stroke_ms) / 1000.0f;
  const float corner_hz = p.get(ParameterId::filter_hz);
  float filter_s = 0.0f;
  switch (p.filter()) {
    case FilterKind::iir: filter_s = 2.0f / (2.0f * float(M_PI) * corner_hz); break;  // two first-order stages
    case FilterKind::average: filter_s = 0.25f / corner_hz; break;                    // half a window
    case FilterKind::none: break;
  }
  return kConservative * (dead_s + 0.5f * stroke_s + filter_s);
}

void FlowBaselineFill::configure(const Parameters& p) {
  jiffy_s_ = p.get(ParameterId::jiffy_ms) / 1000.0f;
  meter_.configure(p);
  blind_.configure(p);
}

void FlowBaselineFill::start(float target_g) {
  meter_.start();
  jiffies_ = 0;
  target_g_ = target_g;
  prediction_g_ = 0.0f;
  at_close_ = AtClose{};
}

}  // namespace dynweigh::firmware
