#include "dynweigh/firmware/learning_table.hpp"

#include <cmath>

namespace dynweigh::firmware {
namespace {
std::uint8_t bucket(float value) {
  const float clamped = value < 0.0f ? 0.0f : (value > 255.0f ? 255.0f : value);
  return std::uint8_t(std::lround(clamped));
}
}  // namespace

LearningKey make_learning_key(float target_g, float final_fall_m, float flow_kg_s) {
  LearningKey key;
  key.target_bucket = bucket(std::log2(target_g > 250.0f ? target_g / 250.0f : 1.0f) * 2.0f);
  key.fall_bucket = bucket(final_fall_m / 0.05f);
  key.flow_bucket = bucket(std::log(flow_kg_s > 0.001f ? flow_kg_s / 0.001f : 1.0f) / std::log(1.05f));
  return key;
}

const LearningTable::Entry* LearningTable::find(const LearningKey& key) const {
  for (const Entry& e : entries_) {
    if (e.used && e.key == key) return &e;
  }
  return nullptr;
}

LearningTable::Entry* LearningTable::find(const LearningKey& key) {
  for (Entry& e : entries_) {
    if (e.used && e.key == key) return &e;
  }
  return nullptr;
}

float LearningTable::correction_g(const LearningKey& key) const {
  const Entry* e = find(key);
  return e ? e->correction_g : 0.0f;
}

void LearningTable::learn(const LearningKey& key, float error_g) {
  if (!(std::fabs(error_g) > kDeadbandG)) return;  // also ignores NaN
  Entry* e = find(key);
  if (!e) {
    for (Entry& candidate : entries_) {
      if (!candidate.used) {
        e = &candidate;
        break;
      }
    }
    if (!e) {  // full: the oldest slot makes room, round robin
      e = &entries_[next_replacement_];
      next_replacement_ = std::uint16_t((next_replacement_ + 1) % kEntries);
    }
    *e = Entry{key, 0.0f, 0, true};
  }
  float step = kGain * error_g;
  step = step > kMaximumStepG ? kMaximumStepG : (step < -kMaximumStepG ? -kMaximumStepG : step);
  // The prediction was short by the error: overfilled means close earlier, so predict more.
  e->correction_g += step;
  if (e->fills < 0xFFFF) ++e->fills;
}

void LearningTable::reset() {
  for (Entry& e : entries_) e = Entry{};
  next_replacement_ = 0;
}

}  // namespace dynweigh::firmware
