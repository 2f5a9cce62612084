#include "dynweigh/sim/pile_avalanches.hpp"

#include <algorithm>

namespace dynweigh::sim {
namespace {

double overlap(double a0, double a1, double b0, double b1) { return std::max(0.0, std::min(a1, b1) - std::max(a0, b0)); }

}  // namespace

double PileAvalanches::step(double landed_kg, double slope_fraction, double begin_s, double end_s) {
  ++steps_;
  added_kg_ += landed_kg;
  // An avalanche triggered during this step starts at its end: the critical mass is known then.
  // More at once than the slots hold slide down together with the ones running: their mass is
  // on the pile either way, and each avalanche's net impulse is zero, so dropping the extra
  // force keeps every balance (and leaves no backlog running on after the stream stops).
  const double duration = std::max(1e-6, parameters_.duration_s * std::clamp(slope_fraction, 0.0, 1.0));
  while (added_kg_ > parameters_.critical_kg) {
    added_kg_ -= parameters_.critical_kg;
    ++started_;
    if (running_count_ < kMaxRunning) running_[running_count_++] = {end_s, duration};
  }
  double impulse_n_s = 0.0;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < running_count_; ++i) {
    const Running r = running_[i];
    const double middle = r.start_s + 0.5 * r.duration_s, stop = r.start_s + r.duration_s;
    impulse_n_s += parameters_.force_n *
                   (overlap(begin_s, end_s, middle, stop) - overlap(begin_s, end_s, r.start_s, middle));
    if (stop > end_s) running_[kept++] = r;
  }
  running_count_ = kept;
  return impulse_n_s / (end_s - begin_s);
}

}  // namespace dynweigh::sim
