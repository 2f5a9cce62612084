#pragma once
// The load cell and its ADC: gain, offset, noise, quantization to whole counts, and the
// overload and underload flags a real converter raises at the ends of its range.
#include <cstdint>

#include "dynweigh/sim/random.hpp"
#include "dynweigh/sim/scene.hpp"

namespace dynweigh::sim {

struct LoadCellSample {
  std::int32_t raw_counts = 0;
  std::uint16_t counter = 0;
  std::uint8_t status = 0;  // SPEC §4: bit0 overload, bit1 underload, bit2 ADC error
};

inline constexpr std::uint8_t kStatusOverload = 0x01;
inline constexpr std::uint8_t kStatusUnderload = 0x02;
inline constexpr std::uint8_t kStatusAdcError = 0x04;

class LoadCell {
 public:
  LoadCell(const LoadCellParameters& parameters, double g, std::uint64_t seed);
  LoadCellSample convert(double force_n);
  // Counts of a force without noise: what the factory calibration sees.
  double ideal_counts(double force_n) const;
  double counts_per_gram() const { return parameters_.counts_per_kg / 1000.0; }

 private:
  LoadCellParameters parameters_;
  double g_;
  Random random_;
  std::uint16_t counter_ = 0;
};

}  // namespace dynweigh::sim
