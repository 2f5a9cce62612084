#pragma once
// OIML R61 accuracy classes for automatic gravimetric filling instruments (docs/benchmarks.md,
// as enacted in UK SI 2000/388 schedule 5 and SI 2006/1258): the maximum permissible deviation
// of each fill from the mean of the fills, for class X(1); class X(x) multiplies it by x.
namespace dynweigh::tools {

struct OimlLimits {
  double initial_verification_g;
  double in_service_g;
};

// Class X(1) limits for a fill of `fill_g` grams.
OimlLimits oiml_x1_limits(double fill_g);

// The best (smallest) class X(x), x in 1, 2, 5 times a power of ten from 0.1 to 100, with every
// fill within x times the initial-verification limit of the mean and |bias| within a quarter of
// x times the in-service limit. 0 when none is met.
double best_oiml_class(double fill_g, double max_deviation_g, double bias_g);

// The smallest class X(x) of the same list whose initial-verification limit holds one fill's
// deviation from its target (a single fill has no mean to be judged against). 0 when none does.
double oiml_class_of_deviation(double fill_g, double deviation_g);

}  // namespace dynweigh::tools
