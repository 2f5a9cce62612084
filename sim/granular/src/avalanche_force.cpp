#include "dynweigh/granular/avalanche_force.hpp"

#include <algorithm>

namespace dynweigh::granular {

namespace {
// Adds `force` over [from, to) to the samples, weighting partly covered samples by overlap so
// the impulse is exact whatever the sample period.
void add_box(double from, double to, double force, double dt, std::vector<double>& signal) {
  if (to <= from || signal.empty()) return;
  const auto first = static_cast<long>(std::floor(from / dt));
  const auto last = static_cast<long>(std::floor(to / dt));
  for (long k = std::max(0L, first); k <= last && k < static_cast<long>(signal.size()); ++k) {
    const double lo = std::max(from, static_cast<double>(k) * dt);
    const double hi = std::min(to, static_cast<double>(k + 1) * dt);
    if (hi > lo) signal[static_cast<std::size_t>(k)] += force * (hi - lo) / dt;
  }
}
}  // namespace

void add_avalanche_force(const Avalanche& avalanche, double start_s, const AvalancheForceModel& model,
                         double sample_period_s, std::vector<double>& force_n) {
  if (!avalanche.happened() || sample_period_s <= 0) return;
  const double tau = model.wave_period_s();
  const double amplitude = model.amplitude_n(avalanche);
  const double end = start_s + static_cast<double>(avalanche.duration) * tau;
  add_box(start_s, start_s + tau, -amplitude, sample_period_s, force_n);
  add_box(end, end + tau, amplitude, sample_period_s, force_n);
}

}  // namespace dynweigh::granular
