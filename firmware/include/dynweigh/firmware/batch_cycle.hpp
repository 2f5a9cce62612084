#pragma once
// A batch: up to kMaxIngredients ingredients dosed one after the other into the same hopper, each
// material from its own valve (material m from ingredient valve m). Weighing is cumulative: each
// ingredient's dose starts from the weight the one before left, with no tare between. The cycle
// only keeps the recipe and the tally; the indicator doses each ingredient as it doses `dose`.
#include <cstddef>
#include <cstdint>

namespace dynweigh::firmware {

struct BatchIngredient {
  std::uint8_t material = 0;  // also the valve it flows from
  std::int32_t grams = 0;
};

// Why a `<material>:<grams>` word was refused.
enum class BatchWordError : std::uint8_t { none, form, material, grams };

class BatchCycle {
 public:
  static constexpr std::size_t kMaxIngredients = 8;  // ingredient valves 0..7

  // `<material>:<grams>`: material 0..7, grams 1..capacity_g, digits only.
  static BatchWordError parse(const char* word, std::int32_t capacity_g, BatchIngredient& out);

  // The recipe (1..kMaxIngredients ingredients), the operator's selected material (restored at the
  // end) and the jiffy it starts in. False, and nothing starts, for an empty or too long recipe.
  bool start(const BatchIngredient* ingredients, std::size_t count, std::size_t operator_material, std::uint32_t jiffy);
  bool active() const { return active_; }
  const BatchIngredient& current() const { return recipe_[index_]; }
  // An ingredient's certified fill: counted; true if another ingredient follows (now current()).
  bool next(std::int32_t final_g);
  // The batch is over (all dosed, or stopped): what the BATCH line says.
  struct Summary {
    std::size_t ingredients = 0;  // certified ones
    std::int64_t total_g = 0;
    std::uint32_t jiffies = 0;
  };
  Summary finish(std::uint32_t jiffy);
  std::size_t operator_material() const { return operator_material_; }

 private:
  BatchIngredient recipe_[kMaxIngredients];
  std::size_t count_ = 0;
  std::size_t index_ = 0;
  std::size_t certified_ = 0;
  std::int64_t total_g_ = 0;
  std::uint32_t start_jiffy_ = 0;
  std::size_t operator_material_ = 0;
  bool active_ = false;
};

}  // namespace dynweigh::firmware
