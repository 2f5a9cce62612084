#pragma once
// The flow factor alpha from the DEM silo (thesis eq. 3.16, mdot = alpha v0 A rho): the profile of
// the downward speed of the discs across the orifice, time-averaged, and alpha = its mean over the
// orifice / its peak, as the Poisson duct flow's mean-to-max ratio (poisson_problem.hpp).
// Plain data plus free functions; sampling allocates nothing.
#include <cstddef>
#include <vector>

#include "dynweigh/granular/dem2d_world.hpp"

namespace dynweigh::granular {

struct OutflowProfile {
  double x_min = 0, x_max = 1;  // the orifice gap
  double y_level = 0;           // the orifice plane
  double band = 0.5;            // discs with |y - y_level| < band are sampled
  std::vector<double> speed_sum;   // per bin: sum of the downward speed of the sampled discs
  std::vector<double> disc_count;  // per bin: discs sampled
  std::size_t samples = 0;         // calls of sample_outflow
};

// A profile of `bins` equal bins over [x_min, x_max] (throws std::invalid_argument if empty).
OutflowProfile make_outflow_profile(double x_min, double x_max, double y_level, double band, int bins);
// The profile across the orifice of the peer silo (silo2d.hpp) with `orifice` wall discs removed:
// the gap between the edges of the remaining bottom discs, at their centres' height.
OutflowProfile make_silo2d_outflow_profile(double silo_width, int orifice, int bins);

// Adds the moving discs within the band (their centres' x in the gap) to the profile.
void sample_outflow(OutflowProfile& profile, const Dem2dWorld& world);

struct OutflowSummary {
  double mean_speed = 0;  // mean over the bins of each bin's mean downward speed (empty bins: 0)
  double peak_speed = 0;  // the largest bin's mean downward speed
  double alpha = 0;       // mean / peak
  double sampled_discs = 0;
};
OutflowSummary summarize_outflow(const OutflowProfile& profile);

}  // namespace dynweigh::granular
