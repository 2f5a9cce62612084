#include "dynweigh/firmware/batch_cycle.hpp"

namespace dynweigh::firmware {
namespace {

// Digits only, at least one, at most `max_digits` (no sign: a material and a weight are positive).
bool parse_digits(const char* begin, const char* end, std::size_t max_digits, std::int64_t& value) {
  if (begin == end || std::size_t(end - begin) > max_digits) return false;
  value = 0;
  for (const char* p = begin; p != end; ++p) {
    if (*p < '0' || *p > '9') return false;
    value = value * 10 + (*p - '0');
  }
  return true;
}

}  // namespace

BatchWordError BatchCycle::parse(const char* word, std::int32_t capacity_g, BatchIngredient& out) {
  const char* colon = word;
  while (*colon && *colon != ':') ++colon;
  if (!*colon) return BatchWordError::form;
  const char* end = colon + 1;
  while (*end) ++end;
  std::int64_t material = 0, grams = 0;
  if (!parse_digits(word, colon, 3, material) || !parse_digits(colon + 1, end, 10, grams)) {
    return BatchWordError::form;
  }
  if (material >= std::int64_t(kMaxIngredients)) return BatchWordError::material;
  if (grams <= 0 || grams > capacity_g) return BatchWordError::grams;
  out.material = std::uint8_t(material);
  out.grams = std::int32_t(grams);
  return BatchWordError::none;
}

bool BatchCycle::start(const BatchIngredient* ingredients, std::size_t count, std::size_t operator_material,
                       std::uint32_t jiffy) {
  if (count == 0 || count > kMaxIngredients) return false;
  for (std::size_t i = 0; i < count; ++i) recipe_[i] = ingredients[i];
  count_ = count;
  index_ = 0;
  certified_ = 0;
  total_g_ = 0;
  start_jiffy_ = jiffy;
  operator_material_ = operator_material;
  active_ = true;
  return true;
}

bool BatchCycle::next(std::int32_t final_g) {
  if (!active_) return false;
  ++certified_;
  total_g_ += final_g;
  if (index_ + 1 >= count_) return false;
  ++index_;
  return true;
}

BatchCycle::Summary BatchCycle::finish(std::uint32_t jiffy) {
  active_ = false;
  return Summary{certified_, total_g_, jiffy - start_jiffy_};
}

}  // namespace dynweigh::firmware
