#pragma once
// The OIML R61 class a series of fills reaches (as enacted in UK SI 2000/388 schedule 5 and
// SI 2006/1258): class X(x) multiplies the X(1) limits by x. The bench grades strategies by it; the
// firmware only needs the limits (oiml_r61_limits.hpp). Host code: double.
#include <cmath>

#include "dynweigh/model/oiml_r61_limits.hpp"

namespace dynweigh::model {

// Class X(1) limits for a fill of `fill_g` grams.
inline OimlR61Limits<double> oiml_x1_limits(double fill_g) { return oiml_r61_x1_limits(fill_g); }

// The classes a fill is graded in: 1, 2, 5 times a power of ten from 0.1 to 100.
inline constexpr double kOimlClasses[] = {0.1, 0.2, 0.5, 1, 2, 5, 10, 20, 50, 100};

// The best (smallest) class X(x) with every fill within x times the initial-verification limit of
// the mean and |bias| within a quarter of x times the in-service limit. 0 when none is met.
inline double best_oiml_class(double fill_g, double max_deviation_g, double bias_g) {
  const OimlR61Limits<double> x1 = oiml_x1_limits(fill_g);
  for (double x : kOimlClasses) {
    if (max_deviation_g <= x * x1.initial_verification_g && std::abs(bias_g) <= x * x1.in_service_g / 4.0) {
      return x;
    }
  }
  return 0.0;
}

// The smallest class whose initial-verification limit holds one fill's deviation from its target
// (a single fill has no mean to be judged against). 0 when none does.
inline double oiml_class_of_deviation(double fill_g, double deviation_g) {
  const OimlR61Limits<double> x1 = oiml_x1_limits(fill_g);
  for (double x : kOimlClasses) {
    if (std::abs(deviation_g) <= x * x1.initial_verification_g) return x;
  }
  return 0.0;
}

}  // namespace dynweigh::model
