#pragma once
// The thesis' recommendation (§4.2): a table of residual corrections learned over fills, keyed by
// what changes the rest-drop: the target, the fall height at the end of the fill, and the
// material's signature (its flow through this bore). The model predicts; the table corrects what the
// model still gets wrong for this kind of fill. Steps are capped, small errors are ignored, and
// only certified fills teach it.
#include <cstddef>
#include <cstdint>

namespace dynweigh::firmware {

struct LearningKey {
  std::uint8_t target_bucket = 0;  // log2 of the target in 250 g units
  std::uint8_t fall_bucket = 0;    // 50 mm bands of the final fall height
  std::uint8_t flow_bucket = 0;    // 5 % bands (log scale) of the measured flow
  bool operator==(const LearningKey& other) const {
    return target_bucket == other.target_bucket && fall_bucket == other.fall_bucket &&
           flow_bucket == other.flow_bucket;
  }
};

LearningKey make_learning_key(float target_g, float final_fall_m, float flow_kg_s);

class LearningTable {
 public:
  static constexpr std::size_t kEntries = 16;
  static constexpr float kGain = 0.5f;       // correct half the residual, as PREACT LEARN does
  static constexpr float kDeadbandG = 1.0f;  // one division: noise, not a lesson
  static constexpr float kMaximumStepG = 50.0f;

  struct Entry {
    LearningKey key;
    float correction_g = 0.0f;  // grams to add to the model's prediction
    std::uint16_t fills = 0;
    bool used = false;
  };

  float correction_g(const LearningKey& key) const;
  // A certified fill of the learn strategy ended `error_g` from its target.
  void learn(const LearningKey& key, float error_g);
  void reset();

  const Entry& entry(std::size_t i) const { return entries_[i]; }
  Entry& entry(std::size_t i) { return entries_[i]; }

 private:
  Entry* find(const LearningKey& key);
  const Entry* find(const LearningKey& key) const;
  Entry entries_[kEntries];
  std::uint16_t next_replacement_ = 0;
};

}  // namespace dynweigh::firmware
