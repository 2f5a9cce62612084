#include "dynweigh/sim/load_cell.hpp"

#include <cmath>

namespace dynweigh::sim {

LoadCell::LoadCell(const LoadCellParameters& parameters, double g, std::uint64_t seed)
    : parameters_(parameters), g_(g), random_(seed) {}

double LoadCell::ideal_counts(double force_n) const {
  return parameters_.zero_counts + parameters_.counts_per_kg * force_n / g_;
}

LoadCellSample LoadCell::convert(double force_n) {
  LoadCellSample sample;
  sample.counter = counter_++;
  double counts = ideal_counts(force_n);
  if (parameters_.noise_counts_rms > 0.0) counts += parameters_.noise_counts_rms * random_.gaussian();
  const double top = parameters_.zero_counts +
                     parameters_.counts_per_kg * parameters_.capacity_kg * parameters_.overload_fraction;
  const double bottom = parameters_.zero_counts - 0.02 * parameters_.counts_per_kg * parameters_.capacity_kg;
  if (counts > top) {
    counts = top;
    sample.status |= kStatusOverload;
  } else if (counts < bottom) {
    counts = bottom;
    sample.status |= kStatusUnderload;
  }
  sample.raw_counts = static_cast<std::int32_t>(std::lround(counts));
  return sample;
}

}  // namespace dynweigh::sim
