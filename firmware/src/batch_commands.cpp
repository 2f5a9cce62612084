// The batch on the console: `batch <m>:<g> [<m>:<g> ...]` doses each ingredient in turn into the
// same hopper, material m from ingredient valve m, each with that material selected (its density
// and class, its statistics, totalizers and logbook records); the operator's selection comes back
// at the end. Each ingredient answers its RESULT line as a dose does; the batch then answers
// `BATCH ingredients= total_g= time= ok=` and OK, or, stopped by a fault or `abort`, ok=0 and the ERR.
#include <cstring>

#include "console_commands.hpp"

namespace dynweigh::firmware {
namespace {
constexpr const char* kBatchUsage = "usage: batch <material>:<grams> [...] [<strategy>]  (up to 8; material 0..7)";
}  // namespace

void ConsoleCommands::batch(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  if (args.count < 2) return console.error(2, kBatchUsage);
  // A last word without a colon names the strategy every ingredient is dosed with.
  DosingStrategy strategy = DosingStrategy::model;
  std::size_t words = args.count;
  const char* last = args.word[args.count - 1];
  if (args.count > 2 && !std::strchr(last, ':') && (last[0] < '0' || last[0] > '9')) {
    if (!parse_strategy(last, strategy)) return console.error(2, "unknown strategy");
    if (!strategy_available(strategy)) return console.error(2, "strategy not in this build");
    --words;
  }
  if (words > 1 + BatchCycle::kMaxIngredients) return console.error(2, "at most 8 ingredients");
  const auto capacity_g = std::int32_t(indicator.settings_.parameters.get(ParameterId::capacity_g));
  BatchIngredient recipe[BatchCycle::kMaxIngredients];
  std::int64_t total_g = 0;
  for (std::size_t i = 1; i < words; ++i) {
    BatchIngredient& ingredient = recipe[i - 1];
    switch (BatchCycle::parse(args.word[i], capacity_g, ingredient)) {
      case BatchWordError::none:
        break;
      case BatchWordError::form:
        return console.error(2, kBatchUsage);
      case BatchWordError::material:
        return console.error(2, "material 0..7 (one per ingredient valve)");
      case BatchWordError::grams:
        return console.error(2, "grams out of range (1..capacity_g)");
    }
    if ((indicator.ingredient_valves_ & (1u << ingredient.material)) == 0) {
      return console.error(2, "no valve for that material on this plant");
    }
    total_g += ingredient.grams;
  }
  if (indicator.reject_if_busy()) return;
  if (indicator.manual_valve_ != ValveCommand::closed) return console.error(3, "valve open (valve 0 first)");
  if (indicator.fault_ != Fault::none) return console.error(4, "fault active");
  if (!indicator.settings_.calibration.valid()) return console.error(5, "not calibrated");
  if (indicator.scale_.filtered_gross_g(indicator.settings_.calibration) + float(total_g) > float(capacity_g)) {
    return console.error(2, "the batch exceeds the scale's capacity");
  }
  indicator.batch_.start(recipe, words - 1, indicator.settings_.materials.selected(), indicator.jiffy_);
  indicator.batch_strategy_ = strategy;
  indicator.start_batch_ingredient();
}

// The current ingredient's material selected (its parameters in force) and its dose started.
void Indicator::start_batch_ingredient() {
  const BatchIngredient& ingredient = batch_.current();
  select_material(ingredient.material);
  use_valve(ingredient.material);
  start_dose(ingredient.material, ingredient.grams, batch_strategy_);
}

void Indicator::select_material(std::size_t n) {
  if (settings_.materials.selected() == n) return;
  settings_.materials.select(n, settings_.parameters);
  // Only the dose reads a material's density (its class is read when a result is judged). The fault
  // supervisor is not configured anew: the last ingredient's after-close watch runs on while the
  // next one waits for rest, and new limits in the middle of it would read a rise that is not there.
  dosing_.configure(settings_.parameters);
  settings_changed_ = true;
}

void Indicator::use_valve(std::uint8_t ingredient) {
  if (ingredient == ingredient_) return;
  ingredient_ = ingredient;
  supervisor_.another_valve();
}

// BATCH and the operator's material back; the valve in force is ingredient 0's again (closed).
void Indicator::end_batch(bool complete) {
  const BatchCycle::Summary s = batch_.finish(jiffy_);
  select_material(batch_.operator_material());
  use_valve(0);
  console_.write("BATCH ingredients=");
  console_.write_int(std::int64_t(s.ingredients));
  console_.write(" total_g=");
  console_.write_int(s.total_g);
  console_.write(" time=");
  console_.write_int(std::int64_t(s.jiffies * std::uint32_t(settings_.parameters.get(ParameterId::jiffy_ms))));
  console_.write(" ok=");
  console_.write_int(complete ? 1 : 0);
  console_.put('\n');
}

}  // namespace dynweigh::firmware
