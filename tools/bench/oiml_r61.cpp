#include "oiml_r61.hpp"

#include <cmath>

namespace dynweigh::tools {

OimlLimits oiml_x1_limits(double m) {
  if (m <= 50.0) return {0.063 * m, 0.09 * m};
  if (m <= 100.0) return {3.15, 4.5};
  if (m <= 200.0) return {0.0315 * m, 0.045 * m};
  if (m <= 300.0) return {6.3, 9.0};
  if (m <= 500.0) return {0.021 * m, 0.03 * m};
  if (m <= 1000.0) return {10.5, 15.0};
  if (m <= 10000.0) return {0.0105 * m, 0.015 * m};
  if (m <= 15000.0) return {105.0, 150.0};
  return {0.007 * m, 0.01 * m};
}

double best_oiml_class(double fill_g, double max_deviation_g, double bias_g) {
  static constexpr double kClasses[] = {0.1, 0.2, 0.5, 1, 2, 5, 10, 20, 50, 100};
  const OimlLimits x1 = oiml_x1_limits(fill_g);
  for (double x : kClasses) {
    if (max_deviation_g <= x * x1.initial_verification_g && std::abs(bias_g) <= x * x1.in_service_g / 4.0) {
      return x;
    }
  }
  return 0.0;
}

}  // namespace dynweigh::tools
