#include "dynweigh/firmware/tolerance.hpp"

#include "dynweigh/model/oiml_r61_limits.hpp"

namespace dynweigh::firmware {
namespace {
float band_or_class(const Parameters& parameters, ParameterId id, float from_class_g) {
  const float set_g = parameters.get(id);
  return set_g > 0.0f ? set_g : from_class_g;
}
}  // namespace

const char* tolerance_verdict_name(ToleranceVerdict verdict) {
  switch (verdict) {
    case ToleranceVerdict::ok: return "ok";
    case ToleranceVerdict::warn_low: return "warn_low";
    case ToleranceVerdict::warn_high: return "warn_high";
    case ToleranceVerdict::low: return "low";
    case ToleranceVerdict::high: return "high";
  }
  return "?";
}

ToleranceBands tolerance_bands(float target_g, const Parameters& parameters) {
  const float x = parameters.get(ParameterId::oiml_class);
  const model::OimlR61Limits<float> x1 = model::oiml_r61_x1_limits(target_g);
  ToleranceBands bands;
  bands.warn_low_g = band_or_class(parameters, ParameterId::tol_warn_low_g, x * x1.initial_verification_g);
  bands.warn_high_g = band_or_class(parameters, ParameterId::tol_warn_high_g, x * x1.initial_verification_g);
  bands.reject_low_g = band_or_class(parameters, ParameterId::tol_reject_low_g, x * x1.in_service_g);
  bands.reject_high_g = band_or_class(parameters, ParameterId::tol_reject_high_g, x * x1.in_service_g);
  return bands;
}

ToleranceVerdict judge_tolerance(float error_g, const ToleranceBands& bands) {
  if (error_g < -bands.reject_low_g) return ToleranceVerdict::low;
  if (error_g > bands.reject_high_g) return ToleranceVerdict::high;
  if (error_g < -bands.warn_low_g) return ToleranceVerdict::warn_low;
  if (error_g > bands.warn_high_g) return ToleranceVerdict::warn_high;
  return ToleranceVerdict::ok;
}

}  // namespace dynweigh::firmware
