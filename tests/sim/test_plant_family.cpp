// The plant family of `dynweigh bench --plants`: every plant inside the physical ranges, the
// ranges actually spanned, the same plants for the same seed, and the test weight `cal` needs.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <string>
#include <vector>

#include "dynweigh/sim/plant.hpp"
#include "dynweigh/sim/plant_family.hpp"

namespace dynweigh::sim {
namespace {

struct Drawn {
  const char* name;
  FamilyRange range;
  std::function<double(const FamilyPlant&)> value;
};

std::vector<Drawn> drawn_fields() {
  const PlantFamilyRanges& r = kPlantFamilyRanges;
  return {
      {"bulk_density", r.bulk_density, [](const FamilyPlant& p) { return p.scene.silo.bulk_density; }},
      {"grain_d_m", r.grain_d_m, [](const FamilyPlant& p) { return p.scene.silo.grain_d_m; }},
      {"beverloo_C", r.beverloo_C, [](const FamilyPlant& p) { return p.scene.silo.beverloo_C; }},
      {"beverloo_k", r.beverloo_k, [](const FamilyPlant& p) { return p.scene.silo.beverloo_k; }},
      {"bore_m", r.bore_m, [](const FamilyPlant& p) { return p.scene.silo.bore_m; }},
      {"fall_height_m", r.fall_height_m, [](const FamilyPlant& p) { return p.scene.column.fall_height_m; }},
      {"container_diameter_m", r.container_diameter_m,
       [](const FamilyPlant& p) { return p.scene.column.container_diameter_m; }},
      {"repose_angle_deg", r.repose_angle_deg, [](const FamilyPlant& p) { return p.scene.column.repose_angle_deg; }},
      {"dead_time_s", r.dead_time_s, [](const FamilyPlant& p) { return p.scene.valve.dead_time_s; }},
      {"dead_time_jitter_fraction", r.dead_time_jitter_fraction,
       [](const FamilyPlant& p) { return p.scene.valve.dead_time_jitter_s / p.scene.valve.dead_time_s; }},
      {"full_stroke_s", r.full_stroke_s, [](const FamilyPlant& p) { return p.scene.valve.full_stroke_s; }},
      {"alpha_settle_s", r.alpha_settle_s, [](const FamilyPlant& p) { return p.scene.silo.alpha_settle_s; }},
      {"alpha_start", r.alpha_start, [](const FamilyPlant& p) { return p.scene.silo.alpha_start; }},
      {"fluctuation_rms", r.fluctuation_rms, [](const FamilyPlant& p) { return p.scene.silo.fluctuation_rms; }},
      {"fluctuation_correlation_s", r.fluctuation_correlation_s,
       [](const FamilyPlant& p) { return p.scene.silo.fluctuation_correlation_s; }},
      {"impact_relaxation_s", r.impact_relaxation_s, [](const FamilyPlant& p) { return p.scene.impact.relaxation_s; }},
      {"platform_hz", r.platform_hz, [](const FamilyPlant& p) { return p.scene.platform.natural_hz; }},
      {"platform_damping", r.platform_damping, [](const FamilyPlant& p) { return p.scene.platform.damping_ratio; }},
      {"moving_mass_kg", r.moving_mass_kg, [](const FamilyPlant& p) { return p.scene.platform.container_kg; }},
      {"zero_counts", r.zero_counts, [](const FamilyPlant& p) { return p.scene.load_cell.zero_counts; }},
      {"counts_per_kg", r.counts_per_kg, [](const FamilyPlant& p) { return p.scene.load_cell.counts_per_kg; }},
      {"noise_divisions", r.noise_divisions,
       [](const FamilyPlant& p) {
         return p.scene.load_cell.noise_counts_rms / (p.scene.load_cell.counts_per_kg * kFamilyDivisionKg);
       }},
      {"silo_volume_m3", r.silo_volume_m3,
       [](const FamilyPlant& p) { return p.scene.silo.fill_kg / p.scene.silo.bulk_density; }},
      {"density_guess_factor", r.density_guess_factor,
       [](const FamilyPlant& p) { return p.density_guess / p.scene.silo.bulk_density; }},
  };
}

TEST(PlantFamily, EveryPlantStaysInsideThePhysicalRangesAndTheDrawSpansThem) {
  const std::vector<FamilyPlant> plants = draw_plant_family(300, 1);
  ASSERT_EQ(plants.size(), 300u);
  for (const Drawn& field : drawn_fields()) {
    SCOPED_TRACE(field.name);
    const double span = field.range.high - field.range.low;
    const double tolerance = 1e-9 * std::max(std::abs(field.range.low), std::abs(field.range.high)) + 1e-12;
    double lowest = field.range.high, highest = field.range.low;
    for (const FamilyPlant& plant : plants) {
      const double v = field.value(plant);
      EXPECT_GE(v, field.range.low - tolerance);
      EXPECT_LE(v, field.range.high + tolerance);
      lowest = std::min(lowest, v);
      highest = std::max(highest, v);
    }
    // 300 draws reach within a tenth of the span of either end (log-uniform ones too).
    EXPECT_LT(lowest, field.range.low + 0.1 * span);
    EXPECT_GT(highest, field.range.high - 0.1 * span);
  }
  for (const FamilyPlant& plant : plants) {
    EXPECT_EQ(plant.scene.load_cell.capacity_kg, kFamilyLoadCellCapacityKg);
    EXPECT_FALSE(plant.scene.platform.rigid);
    EXPECT_TRUE(plant.scene.column.pile_grows);
  }
}

TEST(PlantFamily, TheSameSeedDrawsTheSamePlantsWhateverTheirNumberAndAnotherSeedOthers) {
  const std::vector<FamilyPlant> first = draw_plant_family(20, 7);
  const std::vector<FamilyPlant> again = draw_plant_family(20, 7);
  const std::vector<FamilyPlant> other = draw_plant_family(20, 8);
  std::size_t differing = 0;
  for (std::size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(first[i].scene.name, "random-" + std::to_string(i + 1));
    const FamilyPlant alone = draw_family_plant(7, std::uint32_t(i));
    for (const Drawn& field : drawn_fields()) {
      EXPECT_EQ(field.value(first[i]), field.value(again[i])) << field.name << " of plant " << i;
      EXPECT_EQ(field.value(first[i]), field.value(alone)) << field.name << " of plant " << i;
      differing += field.value(first[i]) != field.value(other[i]);
    }
  }
  EXPECT_EQ(differing, first.size() * drawn_fields().size());
}

TEST(PlantFamily, APlantHoldsATargetItsSiloHoldsWhoseHeapLeavesHalfTheFallAndThatFullFlowDeliversInTime) {
  FamilyPlant plant = draw_family_plant(1, 0);
  Scene& s = plant.scene;
  s.silo.fill_kg = 12.0;
  s.silo.bulk_density = 1500.0;
  s.silo.beverloo_C = 0.58;
  s.silo.beverloo_k = 1.5;
  s.silo.grain_d_m = 0.0005;
  s.silo.bore_m = 0.06;   // 1.6 kg/s
  s.column.fall_height_m = 1.5;
  s.column.container_diameter_m = 0.4;
  EXPECT_TRUE(family_plant_holds(s, 10.0));
  EXPECT_FALSE(family_plant_holds(s, 10.5));  // the silo's reserve
  s.silo.fill_kg = 100.0;
  s.column.container_diameter_m = 0.2;  // 10 kg (6.7 l) stands about 0.25 m high in a 0.2 m tube
  EXPECT_TRUE(family_plant_holds(s, 10.0));
  s.column.fall_height_m = 0.4;          // ...more than half of a 0.4 m fall
  EXPECT_FALSE(family_plant_holds(s, 10.0));
  s.column.fall_height_m = 1.5;
  s.silo.bore_m = 0.015;                 // a trickle of 0.07 kg/s: 10 kg takes over two minutes
  EXPECT_FALSE(family_plant_holds(s, 10.0));
}

TEST(PlantFamily, ATestWeightSetOnThePlatformWeighsAndRingsAndLiftedOffIsGone) {
  Scene scene = draw_family_plant(1, 2).scene;
  scene.load_cell.noise_counts_rms = 0.0;
  scene.platform = PlatformParameters{false, 10.0, 12.0, 0.05};
  Plant plant(scene, 1);
  const double empty_counts = plant.empty_counts();
  plant.place_test_weight(20.0);
  double swing_kg = 0.0;  // a weight set down at once: the platform swings past it
  for (int jiffy = 0; jiffy < 50; ++jiffy) {
    plant.advance(0.01);
    swing_kg = std::max(swing_kg, std::abs(plant.truth().force_n / scene.g - 20.0));
  }
  EXPECT_GT(swing_kg, 5.0);
  plant.advance(60.0);
  const double counts_per_kg = scene.load_cell.counts_per_kg;
  EXPECT_NEAR((plant.sample().raw_counts - empty_counts) / counts_per_kg, 20.0, 2.0 / counts_per_kg + 1e-4);
  EXPECT_EQ(plant.truth().static_kg, 0.0);  // the fill is what landed, never the test weight
  plant.place_test_weight(0.0);
  plant.advance(60.0);
  EXPECT_NEAR((plant.sample().raw_counts - empty_counts) / counts_per_kg, 0.0, 2.0 / counts_per_kg + 1e-4);
}

}  // namespace
}  // namespace dynweigh::sim
