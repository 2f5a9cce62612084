#include "plant_family_ceiling.hpp"

#include <cinttypes>
#include <cstdio>
#include <sstream>
#include <string>

#include "dynweigh/model/oiml_r61_class.hpp"
#include "dynweigh/sim/plant_family.hpp"
#include "fill_ceiling.hpp"
#include "grid_runner.hpp"
#include "progress_bar.hpp"

namespace dynweigh::tools {
namespace {

constexpr int kSamples = 100;          // seeds per action
constexpr int kPulses = 3;             // `topup_max`'s default
constexpr char kCellSeparator = ';';

std::string plant_ceiling(const PlantFamilyOptions& o, std::uint32_t index) {
  const sim::FamilyPlant plant = sim::draw_family_plant(o.plants.seed, index);
  std::string row;
  for (double target_g : o.targets_g) {
    if (!sim::family_plant_holds(plant.scene, target_g / 1000.0)) continue;
    const model::OimlR61Limits<double> x1 = model::oiml_x1_limits(target_g);
    const CeilingActions actions = sample_ceiling_actions(plant.scene, target_g, kSamples);
    const FillCeiling c = fill_ceiling(actions, target_g, {x1.initial_verification_g, x1.in_service_g / 4.0}, kPulses,
                                       o.fills - 1);
    char line[200];
    std::snprintf(line, sizeof line, "ceiling plant=%s target_g=%.0f first=%.3f steady=%.3f", plant.scene.name.c_str(),
                  target_g, c.first, c.steady);
    if (!row.empty()) row += kCellSeparator;
    row += line;
  }
  return row.empty() ? "-" : row;
}

double field(const std::string& line, const char* key) {
  const std::string k = std::string(" ") + key + "=";
  const auto at = line.find(k);
  return at == std::string::npos ? 0.0 : std::strtod(line.c_str() + at + k.size(), nullptr);
}

}  // namespace

void run_plant_family_ceiling(const PlantFamilyOptions& o, const grid::ParallelSession& session) {
  if (o.fills < 2) throw std::runtime_error("--fills must be 2 or more (a first fill and a steady one)");
  std::vector<std::string> keys;
  for (std::uint32_t p = 0; p < o.plants.count; ++p) keys.push_back("ceiling plant=random-" + std::to_string(p + 1));
  ProgressBar bar("bench --plants --ceiling", keys.size(), o.progress && session.writer());
  grid::GridOptions options;
  options.threads = o.threads;
  options.signature = "bench plants ceiling";
  options.progress = [&bar](std::size_t finished, std::size_t) { bar.update(finished); };
  const grid::GridOutcome outcome =
      grid::run_grid(session, keys, [&](std::size_t job) { return plant_ceiling(o, std::uint32_t(job)); }, options);
  bar.finish();
  if (!session.writer()) return;
  std::size_t cells = 0;
  double first = 0.0, steady = 0.0;
  for (const std::string& text : outcome.rows) {
    std::istringstream row(text);
    for (std::string line; std::getline(row, line, kCellSeparator);) {
      if (line == "-") continue;
      std::printf("%s\n", line.c_str());
      ++cells;
      first += field(line, "first");
      steady += field(line, "steady");
    }
  }
  const double n = cells ? double(cells) : 1.0;
  std::printf("summary ceiling plants=%" PRIu32 " seed=%" PRIu64 " fills=%" PRIu32
              " pulses=%d cells=%zu first_x1_share=%.3f steady_x1_share=%.3f\n",
              o.plants.count, o.plants.seed, o.fills, kPulses, cells, first / n, steady / n);
}

}  // namespace dynweigh::tools
