#pragma once
// Statistics of a material's fills, read back from the logbook: count, mean, standard deviation,
// minimum and maximum of the last fills, and the best OIML R61 class X(x) the series meets.
#include <cstddef>
#include <cstdint>

#include "dynweigh/firmware/logbook.hpp"

namespace dynweigh::firmware {

struct FillStatistics {
  std::uint32_t count = 0;
  float mean_g = 0.0f;
  float sd_g = 0.0f;  // sample standard deviation (n - 1); 0 for a single fill
  float min_g = 0.0f;
  float max_g = 0.0f;
  float class_x = 0.0f;  // 0: no class of 0.1..100 met, or no fill
};

// The best class X(x), x in 1, 2, 5 times a power of ten from 0.1 to 100: every fill within x times
// the initial-verification deviation of the mean, and the mean within a quarter of x times the
// in-service deviation of the target. 0 when none is met.
float best_oiml_class(float fill_g, float max_deviation_g, float bias_g);

// The last `last_n` intact records of `material` with a sequence number above `after_sequence`.
FillStatistics fill_statistics(const Logbook& logbook, std::uint8_t material, std::uint32_t after_sequence,
                               std::uint32_t last_n);

}  // namespace dynweigh::firmware
