#pragma once
// The load cell and its ADC: gain, offset, noise, quantization to whole counts, the overload and
// underload flags a real converter raises at the ends of its range, and (where a scene asks for
// it) creep: under a load the output drifts toward `fraction` of it with a first-order time
// constant, stepped exactly over the time between samples.
#include <cstdint>

#include "dynweigh/schema/can_values.hpp"
#include "dynweigh/sim/random.hpp"
#include "dynweigh/sim/scene.hpp"

namespace dynweigh::sim {

struct LoadCellSample {
  std::int32_t raw_counts = 0;
  std::uint16_t counter = 0;
  std::uint8_t status = 0;  // schema::kLoadCell* bits
};

class LoadCell {
 public:
  // `creep` is null when the scene does not run the creep component.
  LoadCell(const LoadCellParameters& parameters, double g, std::uint64_t seed,
           const CreepParameters* creep = nullptr);
  // Converts the force at `time_s` (creep needs the time since the last sample).
  LoadCellSample convert(double force_n, double time_s = 0.0);
  // Counts of a force without noise or creep: what the factory calibration sees.
  double ideal_counts(double force_n) const;
  double counts_per_gram() const { return parameters_.counts_per_kg / 1000.0; }
  double creep_counts() const { return creep_counts_; }
  std::uint64_t conversions() const { return conversions_; }
  std::uint64_t creep_steps() const { return creep_steps_; }

 private:
  void update_creep(double load_counts, double time_s);

  LoadCellParameters parameters_;
  double g_;
  Random random_;
  std::uint16_t counter_ = 0;
  bool creeps_ = false;
  CreepParameters creep_;
  double creep_counts_ = 0.0;
  double last_time_s_ = 0.0;
  double cached_elapsed_s_ = -1.0;
  double cached_creep_share_ = 0.0;
  std::uint64_t conversions_ = 0;
  std::uint64_t creep_steps_ = 0;
};

}  // namespace dynweigh::sim
