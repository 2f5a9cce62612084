#pragma once
// The scale platform is a spring under the container and its load: its frequency falls as the
// load grows, w^2 = k / (M0 + m), and with a fixed damper its damping ratio falls as 1 / sqrt(M).
// `natural_hz` and `damping_ratio` hold with `moving_kg` on the spring (the empty container and the
// platform's own moving part).
#include <cmath>

namespace dynweigh::model {

template <typename Scalar>
struct PlatformRinging {
  Scalar omega_rad_s = 0;
  Scalar damping_ratio = 0;
};

template <typename Scalar>
PlatformRinging<Scalar> platform_ringing(Scalar natural_hz, Scalar damping_ratio, Scalar moving_kg,
                                         Scalar added_kg) {
  const Scalar loaded_kg = moving_kg + (added_kg > Scalar(0) ? added_kg : Scalar(0));
  const Scalar softening = std::sqrt(moving_kg / loaded_kg);
  return {Scalar(2 * M_PI) * natural_hz * softening, damping_ratio * softening};
}

}  // namespace dynweigh::model
