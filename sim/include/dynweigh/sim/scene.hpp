#pragma once
// A scene: the parameters of every component and which effects are switched on. The defaults are
// the thesis' real setup (its section 2.2, table 2.2) with the disturbances of the default scene (docs/scenes.md).
// Scenes other than the two built in here live as JSON files in scenes/ (scene_file.hpp).
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace dynweigh::sim {

struct SiloParameters {
  double bore_m = 0.060;                 // thesis table 2.2
  double bulk_density = 1550.0;          // dry sand, kg/m^3 (docs/physics.md)
  double beverloo_C = 0.58;              // docs/physics.md
  double beverloo_k = 1.5;               // docs/physics.md
  double grain_d_m = 0.0005;             // docs/physics.md
  double fill_kg = 18.0;                 // "approximately 18 kg of dry sand"
  double alpha_start = 0.6;              // flow fraction at the first instant of opening
  double alpha_settle_s = 0.15;          // start-up settling time constant of alpha
  double fluctuation_rms = 0.03;         // docs/scenes.md
  double fluctuation_correlation_s = 0.15;  // docs/scenes.md
  // Thesis eq. 3.16 (mdot = alpha v0 A rho): the outflow's mean-to-peak speed across the bore,
  // from `dynweigh calibrate --from dem|fluid`; 1 is plug flow. The plant takes the rate from
  // Beverloo and v0 as the mean speed mdot / (A rho), so alpha is the scene's record of the
  // profile (the peak speed is v0 / alpha) and does not change the step.
  double flow_factor = 1.0;
  // Upstream supply: when the silo holds less than refill_below_kg it is refilled at
  // refill_rate_kg_s up to fill_kg (a level switch and a feeder). 0: never refilled, the silo
  // runs dry as the thesis' rig does.
  double refill_below_kg = 0.0;
  double refill_rate_kg_s = 5.0;
};

struct ValveParameters {
  double dead_time_s = 0.030;            // docs/scenes.md
  double dead_time_jitter_s = 0.002;     // docs/scenes.md, rms
  double full_stroke_s = 0.080;          // docs/scenes.md, fast; slow: 0.200
};

// The discharge gate under the weigh hopper: it strokes linearly open or shut, and the hopper
// empties through it at a rate proportional to the stroke. Closed (the default) it changes nothing.
struct GateParameters {
  double discharge_kg_s = 4.0;           // out of the hopper through the open gate
  double stroke_s = 0.5;                 // closed to open (and back)
};

struct ColumnParameters {
  double fall_height_m = 1.200;          // orifice to the empty container's floor, table 2.2
  double container_diameter_m = 0.300;
  double repose_angle_deg = 32.0;        // dry sand
  bool pile_grows = true;                // false: constant h (ideal model)
};

// The top the stream makes (thesis §2.3.1, fig. 2.4): flattened to a plateau the width of the
// stream's footprint, and dented under the stream while it lands. Changes h only, never mass.
struct PileTopParameters {
  bool enabled = false;
  double flat_radius_m = 0.030;          // plateau radius: about half the 60 mm stream
  double dent_depth_m = 0.010;           // crater depth under the full-open stream
  double dent_settle_s = 0.20;           // time the crater takes to form or fill
};

struct ImpactParameters {
  double relaxation_s = 0.010;           // dispersion of landing grains (thesis §1.3, §2.3)
};

// Thesis example 3.2: when the mass added at the top since the last avalanche exceeds a critical
// mass, an avalanche runs for a duration that grows with the slope length (§3.2). The material
// slides down and stops: the scale feels a dip of -F_a then a push of +F_a, so no net impulse.
struct AvalancheParameters {
  bool enabled = false;
  double critical_kg = 0.050;
  double force_n = 0.5;                  // F_a, the avalanche force factor
  double duration_s = 0.040;             // on a slope spanning the whole container
};

struct PlatformParameters {
  bool rigid = false;
  double container_kg = 4.0;
  double natural_hz = 12.0;              // docs/scenes.md, with the empty container
  double damping_ratio = 0.05;           // docs/scenes.md
};

struct LoadCellParameters {
  double capacity_kg = 50.0;             // 50,000 d of 1 g
  double counts_per_kg = 1000.0;         // one count per scale division
  double zero_counts = 8000.0;           // ADC offset of the unloaded cell
  double noise_counts_rms = 0.3;         // docs/scenes.md: 0.3 d
  double overload_fraction = 1.1;        // saturates above 110 % of capacity
};

// Load-cell creep: under a constant load the output drifts by `fraction` of the load with a
// first-order time constant. OIML R60 class C3 allows 0.7 x 0.0245 % over 30 min; this default
// sits at that limit.
struct CreepParameters {
  bool enabled = false;
  double fraction = 0.00017;
  double time_constant_s = 600.0;
};

// Thesis fig. 2.2b: silo and container both stand on the scale, so the mass on it never changes
// and only the dynamic effects show. The reading is taken relative to the loaded rest weight.
struct HourglassParameters {
  bool enabled = false;
  double silo_tare_kg = 10.0;            // the empty silo, its frame and the extra plate
};

// One of up to kMaxIngredients streams into the one weigh hopper: its own silo (material and
// bore), valve and orifice height above the container floor. Ingredient 0 is the scene's silo,
// valve and column.fall_height_m.
struct IngredientParameters {
  std::string material;
  SiloParameters silo;
  ValveParameters valve;
  double fall_height_m = 1.200;
};

inline constexpr std::size_t kMaxIngredients = 8;

struct Scene {
  std::string name = "default";
  std::string source = "thesis table 2.2 (real setup), disturbances of docs/scenes.md";
  double g = 9.81;
  double internal_step_s = 0.001;        // plant steps per 10 ms jiffy: 10
  SiloParameters silo;
  ValveParameters valve;
  GateParameters gate;
  ColumnParameters column;
  PileTopParameters pile_top;
  ImpactParameters impact;
  AvalancheParameters avalanche;
  PlatformParameters platform;
  LoadCellParameters load_cell;
  CreepParameters creep;
  HourglassParameters hourglass;
  // Empty: one ingredient, the silo and valve above. Otherwise every ingredient in valve order
  // (2..kMaxIngredients); entry 0 repeats silo, valve and column.fall_height_m (the loader keeps
  // them equal).
  std::vector<IngredientParameters> ingredients;
};

Scene default_scene();
Scene ideal_scene();  // thesis chapter 1: instant valve, constant h, rigid scale, no noise

// A built-in name, a file scenes/<name>.json, or a path ending in .json. A file overrides the
// built-in of the same name. Returns nullopt for an unknown name; throws std::runtime_error
// naming the field when a scene file is malformed.
std::optional<Scene> scene_by_name(const std::string& name);
// Built-in names and the scene files found, sorted, each once.
std::vector<std::string> scene_names();

}  // namespace dynweigh::sim
