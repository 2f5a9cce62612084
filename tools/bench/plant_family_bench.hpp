#pragma once
// `dynweigh bench --plants random:N[@SEED]`: each strategy on a family of plants it was never tuned
// on, each plant commissioned through the console from a blank indicator, each target dosed a few
// times back to back; judged by the plant's true mass.
#include <cstdint>
#include <string>
#include <vector>

#include "parallel_session.hpp"

namespace dynweigh::tools {

struct PlantFamilySpec {
  std::uint32_t count = 0;
  std::uint64_t seed = 1;
};

// "random:N" or "random:N@SEED" (N 1..10000, SEED a whole number); throws std::runtime_error saying why not.
PlantFamilySpec parse_plant_family_spec(const std::string& text);

struct PlantFamilyOptions {
  PlantFamilySpec plants;
  std::vector<std::string> strategies;  // the words `dose` takes (twostage-dyn: twostage, certified dynamically)
  std::vector<double> targets_g;        // dosed in this order, those each plant holds
  std::uint32_t fills = 6;              // per target, back to back
  unsigned threads = 1;
  bool progress = true;
};

inline const std::vector<double> kPlantFamilyTargetsG{500, 1000, 2000, 5000, 10000, 15000};

// Prints one key=value line per strategy x plant x target, then a summary line per strategy.
void run_plant_family_bench(const PlantFamilyOptions& options, const grid::ParallelSession& session);

}  // namespace dynweigh::tools
