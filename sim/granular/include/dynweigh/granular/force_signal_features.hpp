#pragma once
// The figures by which a dose's force signal on the scale is compared, DEM against the lumped
// plant, each computed the same way on both:
// - dead time: from the open command to the first landing (the start of the rise);
// - impulse: the impact force of the stream as it starts to land, the step P of the
//   impact-relaxation fit (impact_relaxation_estimate.hpp), N;
// - slope: the growth of the load while the stream lands steadily, N/s (flow rate times g);
// - relaxation: the fit's time constant;
// - final: the mean force over the last `final_window_s` of the record, N (released mass g).
#include <vector>

namespace dynweigh::granular {

struct ForceSignalFeatures {
  bool valid = false;
  double dead_time_s = 0;
  double impulse_n = 0;
  double slope_n_s = 0;
  double relaxation_s = 0;
  double final_n = 0;
};

// `steady_end_s`: the last time at which the stream still lands as it did with the gate open
// (before the close can have reached the container).
ForceSignalFeatures force_signal_features(const std::vector<double>& time_s, const std::vector<double>& force_n,
                                          double steady_end_s, double final_window_s = 0.1);

// Relative deviation |a - b| / |b| (0 when both are 0).
double relative_deviation(double a, double b);

}  // namespace dynweigh::granular
