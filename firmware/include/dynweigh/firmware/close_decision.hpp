#pragma once
// A baseline's verdict for the coming jiffy: keep the valve as it is, or close it, `fraction` of the
// way into the jiffy (the valve module's delay byte) when the prediction crosses the target there.
namespace dynweigh::firmware {

struct CloseDecision {
  bool close = false;
  float fraction = 0.0f;  // [0, 0.99]
};

// A prediction now and its growth over the coming jiffy, against the target.
inline CloseDecision close_within_jiffy(float predicted_g, float growth_per_jiffy_g, float target_g) {
  CloseDecision d;
  if (predicted_g + growth_per_jiffy_g < target_g) return d;
  d.close = true;
  const float fraction = growth_per_jiffy_g > 0.0f ? (target_g - predicted_g) / growth_per_jiffy_g : 0.0f;
  d.fraction = fraction < 0.0f ? 0.0f : (fraction > 0.99f ? 0.99f : fraction);
  return d;
}

}  // namespace dynweigh::firmware
