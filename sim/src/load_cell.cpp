#include "dynweigh/sim/load_cell.hpp"

#include <cmath>

namespace dynweigh::sim {

LoadCell::LoadCell(const LoadCellParameters& parameters, double g, std::uint64_t seed, const CreepParameters* creep)
    : parameters_(parameters), g_(g), random_(seed), creeps_(creep != nullptr), creep_(creep ? *creep : CreepParameters{}) {}

double LoadCell::ideal_counts(double force_n) const {
  return parameters_.zero_counts + parameters_.counts_per_kg * force_n / g_;
}

void LoadCell::update_creep(double load_counts, double time_s) {
  ++creep_steps_;
  const double elapsed = time_s - last_time_s_;
  last_time_s_ = time_s;
  if (elapsed <= 0.0) return;
  if (elapsed != cached_elapsed_s_) {  // samples come every jiffy: one expm1 per run
    cached_elapsed_s_ = elapsed;
    cached_creep_share_ = -std::expm1(-elapsed / creep_.time_constant_s);
  }
  creep_counts_ += (creep_.fraction * load_counts - creep_counts_) * cached_creep_share_;
}

LoadCellSample LoadCell::convert(double force_n, double time_s) {
  ++conversions_;
  LoadCellSample sample;
  sample.counter = counter_++;
  double counts = ideal_counts(force_n);
  if (creeps_) {
    update_creep(counts - parameters_.zero_counts, time_s);
    counts += creep_counts_;
  }
  if (parameters_.noise_counts_rms > 0.0) counts += parameters_.noise_counts_rms * random_.gaussian();
  const double top = parameters_.zero_counts +
                     parameters_.counts_per_kg * parameters_.capacity_kg * parameters_.overload_fraction;
  const double bottom = parameters_.zero_counts - 0.02 * parameters_.counts_per_kg * parameters_.capacity_kg;
  if (counts > top) {
    counts = top;
    sample.status |= schema::kLoadCellOverload;
  } else if (counts < bottom) {
    counts = bottom;
    sample.status |= schema::kLoadCellUnderload;
  }
  sample.raw_counts = static_cast<std::int32_t>(std::lround(counts));
  return sample;
}

}  // namespace dynweigh::sim
