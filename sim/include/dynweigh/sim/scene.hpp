#pragma once
// A scene: the parameters of every component and which effects are switched on. The defaults are
// the thesis' real setup (shared/seed §2.2, table 2.2) with the disturbances fixed by SPEC §2.
#include <optional>
#include <string>
#include <vector>

namespace dynweigh::sim {

struct SiloParameters {
  double bore_m = 0.060;                 // thesis table 2.2
  double bulk_density = 1550.0;          // dry sand, kg/m^3 (PHYSICS §3)
  double beverloo_C = 0.58;              // PHYSICS §3
  double beverloo_k = 1.5;               // PHYSICS §3
  double grain_d_m = 0.0005;             // PHYSICS §3
  double fill_kg = 18.0;                 // "approximately 18 kg of dry sand"
  double alpha_start = 0.6;              // flow fraction at the first instant of opening
  double alpha_settle_s = 0.15;          // start-up settling time constant of alpha
  double fluctuation_rms = 0.03;         // SPEC §2
  double fluctuation_correlation_s = 0.15;  // SPEC §2
};

struct ValveParameters {
  double dead_time_s = 0.030;            // SPEC §2
  double dead_time_jitter_s = 0.002;     // SPEC §2, rms
  double full_stroke_s = 0.080;          // SPEC §2, fast; slow: 0.200
};

struct ColumnParameters {
  double fall_height_m = 1.200;          // orifice to the empty container's floor, table 2.2
  double container_diameter_m = 0.300;
  double repose_angle_deg = 32.0;        // dry sand
  bool pile_grows = true;                // false: constant h (ideal model)
};

struct ImpactParameters {
  double relaxation_s = 0.010;           // dispersion of landing grains (thesis §1.3, §2.3)
};

struct PlatformParameters {
  bool rigid = false;
  double container_kg = 4.0;
  double natural_hz = 12.0;              // SPEC §2, with the empty container
  double damping_ratio = 0.05;           // SPEC §2
};

struct LoadCellParameters {
  double capacity_kg = 50.0;             // 50,000 d of 1 g
  double counts_per_kg = 1000.0;         // one count per scale division
  double zero_counts = 8000.0;           // ADC offset of the unloaded cell
  double noise_counts_rms = 0.3;         // SPEC §2: 0.3 d
  double overload_fraction = 1.1;        // saturates above 110 % of capacity
};

struct Scene {
  std::string name = "default";
  double g = 9.81;
  double internal_step_s = 0.001;        // plant steps per 10 ms jiffy: 10
  SiloParameters silo;
  ValveParameters valve;
  ColumnParameters column;
  ImpactParameters impact;
  PlatformParameters platform;
  LoadCellParameters load_cell;
};

Scene default_scene();
Scene ideal_scene();  // thesis chapter 1: instant valve, constant h, rigid scale, no noise
std::optional<Scene> scene_by_name(const std::string& name);
std::vector<std::string> scene_names();

}  // namespace dynweigh::sim
