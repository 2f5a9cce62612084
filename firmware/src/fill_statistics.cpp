#include "dynweigh/firmware/fill_statistics.hpp"

#include <cmath>

#include "dynweigh/model/oiml_r61_limits.hpp"

namespace dynweigh::firmware {
namespace {

constexpr float kClasses[] = {0.1f, 0.2f, 0.5f, 1.0f, 2.0f, 5.0f, 10.0f, 20.0f, 50.0f, 100.0f};

// Walks the newest matching records, newest first, at most `last_n`.
template <typename Visit>
void for_each_fill(const Logbook& logbook, std::uint8_t material, std::uint32_t after_sequence,
                   std::uint32_t last_n, Visit visit) {
  const std::uint32_t first = logbook.first_sequence();
  std::uint32_t seen = 0;
  for (std::uint32_t sequence = logbook.last_sequence(); sequence >= first && sequence > after_sequence && seen < last_n;
       --sequence) {
    LogRecord r;
    if (!logbook.read(sequence, r) || r.material != material) continue;
    visit(r);
    ++seen;
  }
}

}  // namespace

float best_oiml_class(float fill_g, float max_deviation_g, float bias_g) {
  const model::OimlR61Limits<float> x1 = model::oiml_r61_x1_limits(fill_g);
  for (float x : kClasses) {
    if (max_deviation_g <= x * x1.initial_verification_g && std::fabs(bias_g) <= x * x1.in_service_g / 4.0f) {
      return x;
    }
  }
  return 0.0f;
}

FillStatistics fill_statistics(const Logbook& logbook, std::uint8_t material, std::uint32_t after_sequence,
                               std::uint32_t last_n) {
  FillStatistics s;
  float sum = 0.0f, target_sum = 0.0f;
  for_each_fill(logbook, material, after_sequence, last_n, [&](const LogRecord& r) {
    const float final_g = float(r.final_dg) / 10.0f;
    s.min_g = s.count == 0 || final_g < s.min_g ? final_g : s.min_g;
    s.max_g = s.count == 0 || final_g > s.max_g ? final_g : s.max_g;
    sum += final_g;
    target_sum += float(r.target_dg) / 10.0f;
    ++s.count;
  });
  if (s.count == 0) return s;
  s.mean_g = sum / float(s.count);
  const float mean_target_g = target_sum / float(s.count);
  // Second pass: the deviations from the mean (a float sum of squares of kilograms would drown them).
  float squares = 0.0f, max_deviation = 0.0f;
  for_each_fill(logbook, material, after_sequence, last_n, [&](const LogRecord& r) {
    const float deviation = float(r.final_dg) / 10.0f - s.mean_g;
    squares += deviation * deviation;
    max_deviation = std::fabs(deviation) > max_deviation ? std::fabs(deviation) : max_deviation;
  });
  s.sd_g = s.count > 1 ? std::sqrt(squares / float(s.count - 1)) : 0.0f;
  s.class_x = best_oiml_class(mean_target_g, max_deviation, s.mean_g - mean_target_g);
  return s;
}

}  // namespace dynweigh::firmware
