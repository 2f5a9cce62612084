#include "oiml_r61.hpp"

#include <cmath>

#include "dynweigh/model/oiml_r61_limits.hpp"

namespace dynweigh::tools {

OimlLimits oiml_x1_limits(double m) {
  const model::OimlR61Limits<double> x1 = model::oiml_r61_x1_limits(m);
  return {x1.initial_verification_g, x1.in_service_g};
}

namespace {
constexpr double kClasses[] = {0.1, 0.2, 0.5, 1, 2, 5, 10, 20, 50, 100};
}

double best_oiml_class(double fill_g, double max_deviation_g, double bias_g) {
  const OimlLimits x1 = oiml_x1_limits(fill_g);
  for (double x : kClasses) {
    if (max_deviation_g <= x * x1.initial_verification_g && std::abs(bias_g) <= x * x1.in_service_g / 4.0) {
      return x;
    }
  }
  return 0.0;
}

double oiml_class_of_deviation(double fill_g, double deviation_g) {
  const OimlLimits x1 = oiml_x1_limits(fill_g);
  for (double x : kClasses) {
    if (std::abs(deviation_g) <= x * x1.initial_verification_g) return x;
  }
  return 0.0;
}

}  // namespace dynweigh::tools
