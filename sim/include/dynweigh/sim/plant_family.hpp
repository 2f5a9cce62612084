#pragma once
// A family of plants drawn at random across the physical ranges a dosing indicator meets in the
// field: material, gate, geometry, valve, flow, platform and load cell. A plant is a scene of the
// simulator plus what its integrator gets wrong at commissioning (the density guess). The draw is
// a pure function of the seed and the plant's index, the same on every compiler.
#include <cstdint>
#include <vector>

#include "dynweigh/sim/scene.hpp"

namespace dynweigh::sim {

struct FamilyRange {
  double low;
  double high;
};

// The ranges the family is drawn from (uniform, except the grain: log-uniform over its 60x span).
struct PlantFamilyRanges {
  FamilyRange bulk_density{400.0, 2000.0};        // kg/m^3
  FamilyRange grain_d_m{0.0001, 0.006};
  FamilyRange beverloo_C{0.5, 0.65};
  FamilyRange beverloo_k{1.3, 1.7};
  FamilyRange bore_m{0.030, 0.120};
  FamilyRange fall_height_m{0.5, 3.0};
  FamilyRange container_diameter_m{0.2, 1.0};
  FamilyRange repose_angle_deg{25.0, 40.0};
  FamilyRange dead_time_s{0.010, 0.080};
  FamilyRange dead_time_jitter_fraction{0.05, 0.15};  // rms, of the dead time
  FamilyRange full_stroke_s{0.040, 0.300};
  FamilyRange alpha_settle_s{0.05, 0.5};           // the flow's start-up time constant
  FamilyRange alpha_start{0.3, 0.8};                // the flow's fraction at the first instant
  FamilyRange fluctuation_rms{0.01, 0.06};
  FamilyRange fluctuation_correlation_s{0.05, 0.3};
  FamilyRange impact_relaxation_s{0.005, 0.040};
  FamilyRange platform_hz{5.0, 30.0};
  FamilyRange platform_damping{0.02, 0.1};
  FamilyRange moving_mass_kg{4.0, 40.0};
  FamilyRange zero_counts{-5.0e6, 5.0e6};           // the ADC's offset under the empty platform
  FamilyRange counts_per_kg{1000.0, 50000.0};       // log-uniform: a count is 1 g to 0.02 g
  FamilyRange noise_divisions{0.1, 3.0};            // rms, in scale divisions of 1 g
  FamilyRange silo_volume_m3{0.010, 0.040};         // what the silo holds, filled to the top
  FamilyRange density_guess_factor{0.6, 1.4};       // the integrator's `density`, times the truth
};

inline constexpr PlantFamilyRanges kPlantFamilyRanges{};

// The load cell under every family plant: rated for Max (50 kg, the indicator's default, in 1 g
// divisions) over the heaviest moving mass, so the dead load never eats into the weighing range.
inline constexpr double kFamilyLoadCellCapacityKg = 100.0;
inline constexpr double kFamilyDivisionKg = 0.001;

struct FamilyPlant {
  Scene scene;
  double density_guess = 0.0;  // kg/m^3: what the integrator types as `density`
};

// Plant `index` of the family `seed`: independent of how many plants are drawn.
FamilyPlant draw_family_plant(std::uint64_t seed, std::uint32_t index);
std::vector<FamilyPlant> draw_plant_family(std::uint32_t count, std::uint64_t seed);

// Whether the plant can dose `target_kg` as installed: the silo holds it with a reserve of a fifth,
// the heap of it leaves at least half the fall free below the orifice, and full flow delivers it
// well within the indicator's default dose timeout (100 s of 120 s).
bool family_plant_holds(const Scene& scene, double target_kg);

}  // namespace dynweigh::sim
