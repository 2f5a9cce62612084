#pragma once
// The impact relaxation time of the lumped plant (sim/impact_relaxation.hpp: landed momentum
// reaches the scale through a first-order lag tau) from a DEM force signal on the container
// bottom after a stream starts to land on it.
//
// Model: load(t) = 0 before the landing t0, then P (1 - exp(-(t - t0) / tau)) + b (t - t0): the
// impact force P of the stream relaxes in, while the landed weight grows at b. The late part of
// the signal is the asymptote A(t) = P + b (t - t0), fitted by least squares; the area between the
// asymptote and the signal from t0 on is P tau, so tau = area / A(t0). The integral makes the
// estimate insensitive to the collision noise of a DEM force.
#include <vector>

namespace dynweigh::granular {

struct ImpactRelaxationEstimate {
  bool valid = false;
  double landing_time = 0;     // t0: start of the rise that reaches `threshold` of the late load
  double step_force = 0;       // P = A(t0)
  double load_slope = 0;       // b, the landed weight's growth
  double relaxation_time = 0;  // tau
};

// `time` ascending, `load` the downward force on the container (positive); the asymptote is fitted
// over the last `late_fraction` of the record after the landing.
ImpactRelaxationEstimate estimate_impact_relaxation(const std::vector<double>& time, const std::vector<double>& load,
                                                    double threshold = 0.05, double late_fraction = 0.5);

}  // namespace dynweigh::granular
