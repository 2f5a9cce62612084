#include "dynweigh/sim/plant_family.hpp"

#include <cmath>
#include <string>

#include "dynweigh/model/beverloo.hpp"
#include "dynweigh/sim/pile.hpp"
#include "dynweigh/sim/random.hpp"

namespace dynweigh::sim {
namespace {

constexpr double kSiloReserve = 1.2;          // the silo holds a fifth more than the target
constexpr double kFreeFallShare = 0.5;        // the heap leaves half the fall below the orifice
constexpr double kLongestFullFlowS = 100.0;   // the dose timeout is 120 s by default

double uniform(Random& random, const FamilyRange& range) {
  return range.low + (range.high - range.low) * random.uniform();
}

double log_uniform(Random& random, const FamilyRange& range) {
  return range.low * std::exp(std::log(range.high / range.low) * random.uniform());
}

// One stream per plant, so plant i is the same whether 2 or 200 are drawn.
std::uint64_t plant_seed(std::uint64_t seed, std::uint32_t index) {
  return ((seed + 1) * 0xD1B54A32D192ED03ULL) ^ ((std::uint64_t(index) + 1) * 0x9E3779B97F4A7C15ULL);
}

}  // namespace

FamilyPlant draw_family_plant(std::uint64_t seed, std::uint32_t index) {
  const PlantFamilyRanges& r = kPlantFamilyRanges;
  Random random(plant_seed(seed, index));
  FamilyPlant plant;
  Scene& s = plant.scene;  // the defaults' switches: pile grows, no pile top, avalanche or creep
  s.name = "random-" + std::to_string(index + 1);
  s.source = "dynweigh bench --plants random:N@" + std::to_string(seed) + ", plant " + std::to_string(index + 1);
  // Each field takes its draw in a fixed order: a new field goes at the end, so the family's
  // existing plants stay as they were.
  s.silo.bulk_density = uniform(random, r.bulk_density);
  s.silo.grain_d_m = log_uniform(random, r.grain_d_m);
  s.silo.beverloo_C = uniform(random, r.beverloo_C);
  s.silo.beverloo_k = uniform(random, r.beverloo_k);
  s.silo.bore_m = uniform(random, r.bore_m);
  s.column.fall_height_m = uniform(random, r.fall_height_m);
  s.column.container_diameter_m = uniform(random, r.container_diameter_m);
  s.column.repose_angle_deg = uniform(random, r.repose_angle_deg);
  s.valve.dead_time_s = uniform(random, r.dead_time_s);
  s.valve.dead_time_jitter_s = s.valve.dead_time_s * uniform(random, r.dead_time_jitter_fraction);
  s.valve.full_stroke_s = uniform(random, r.full_stroke_s);
  s.silo.alpha_settle_s = uniform(random, r.alpha_settle_s);
  s.silo.alpha_start = uniform(random, r.alpha_start);
  s.silo.fluctuation_rms = uniform(random, r.fluctuation_rms);
  s.silo.fluctuation_correlation_s = uniform(random, r.fluctuation_correlation_s);
  s.impact.relaxation_s = uniform(random, r.impact_relaxation_s);
  s.platform.natural_hz = uniform(random, r.platform_hz);
  s.platform.damping_ratio = uniform(random, r.platform_damping);
  s.platform.container_kg = uniform(random, r.moving_mass_kg);
  s.load_cell.capacity_kg = kFamilyLoadCellCapacityKg;
  s.load_cell.zero_counts = std::round(uniform(random, r.zero_counts));
  s.load_cell.counts_per_kg = log_uniform(random, r.counts_per_kg);
  s.load_cell.noise_counts_rms =
      uniform(random, r.noise_divisions) * s.load_cell.counts_per_kg * kFamilyDivisionKg;
  s.silo.fill_kg = s.silo.bulk_density * uniform(random, r.silo_volume_m3);
  plant.density_guess = s.silo.bulk_density * uniform(random, r.density_guess_factor);
  return plant;
}

std::vector<FamilyPlant> draw_plant_family(std::uint32_t count, std::uint64_t seed) {
  std::vector<FamilyPlant> plants;
  plants.reserve(count);
  for (std::uint32_t i = 0; i < count; ++i) plants.push_back(draw_family_plant(seed, i));
  return plants;
}

bool family_plant_holds(const Scene& scene, double target_kg) {
  if (scene.silo.fill_kg < kSiloReserve * target_kg) return false;
  Pile pile(scene.column, nullptr, scene.silo.bulk_density);
  if (pile.top_height_m(target_kg) > (1.0 - kFreeFallShare) * scene.column.fall_height_m) return false;
  const model::BeverlooMaterial<double> material{scene.silo.beverloo_C, scene.silo.beverloo_k, scene.silo.grain_d_m,
                                                 scene.silo.bulk_density};
  const double full_flow_kg_s = model::beverloo_discharge_kg_s(material, scene.g, scene.silo.bore_m);
  return full_flow_kg_s > 0.0 && target_kg / full_flow_kg_s <= kLongestFullFlowS;
}

}  // namespace dynweigh::sim
