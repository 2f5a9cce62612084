#include "dynweigh/granular/force_signal_features.hpp"

#include <cmath>

#include "dynweigh/granular/impact_relaxation_estimate.hpp"

namespace dynweigh::granular {

ForceSignalFeatures force_signal_features(const std::vector<double>& time_s, const std::vector<double>& force_n,
                                          double steady_end_s, double final_window_s) {
  ForceSignalFeatures f;
  if (time_s.size() != force_n.size() || time_s.empty()) return f;
  std::vector<double> t, load;
  for (std::size_t k = 0; k < time_s.size() && time_s[k] <= steady_end_s; ++k) {
    t.push_back(time_s[k]);
    load.push_back(force_n[k]);
  }
  // The asymptote over the last three quarters of the landing: a DEM's force is noisy, and the
  // relaxation (tens of ms) is over long before.
  const ImpactRelaxationEstimate e = estimate_impact_relaxation(t, load, 0.05, 0.75);
  double sum = 0, count = 0;
  for (std::size_t k = 0; k < time_s.size(); ++k) {
    if (time_s[k] >= time_s.back() - final_window_s) {
      sum += force_n[k];
      count += 1;
    }
  }
  f.final_n = count > 0 ? sum / count : 0.0;
  // A landing was found (the relaxation may come out at or below 0 on a DEM signal: a force that
  // rises as fast as a step, within the noise).
  f.valid = e.step_force > 0 && e.landing_time > 0;
  f.dead_time_s = e.landing_time;
  f.impulse_n = e.step_force;
  f.slope_n_s = e.load_slope;
  f.relaxation_s = e.relaxation_time;
  return f;
}

double relative_deviation(double a, double b) {
  if (a == b) return 0.0;
  return std::fabs(a - b) / std::fabs(b);
}

}  // namespace dynweigh::granular
