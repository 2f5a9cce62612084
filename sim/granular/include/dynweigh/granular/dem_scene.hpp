#pragma once
// A dosing scene as a 2D DEM: a flat-bottom silo with a slide gate over a slot orifice, the free
// fall, and a container on the scale; the output is the force on the container over time, the
// signal the lumped plant (sim/plant.hpp) produces for the same scene.
//
// Scaling (what a 2D DEM of a 60 mm bore must give up):
// - 2D slot: the scene's round bore of diameter D becomes a slot of width D whose depth is
//   pi D / 4, so slot and bore have the same open area; each disc is a slice of that depth.
// - Coarse grains: D is spanned by `discs_across_orifice` discs (8: d = 7.5 mm for the default
//   scene, not 0.5 mm sand), diameters uniform in [0.9, 1.1] d. Disc density is the scene's bulk
//   density over a 2D packing fraction, so a settled bed has about the scene's bulk density.
// - Lengths the discs see are the scene's: fall height, container width, bore; g is real.
// - The silo is `silo_width_bores` bores wide and holds `fill_discs` discs: enough for the
//   opening time, not the scene's 18 kg.
// - Contacts: the LAMMPS silo's (in.silo2d.*: k_n 2e4, gamma_n 97, mu 0.5 in units
//   of d, disc mass and sqrt(d/g)), time step 5e-4 sqrt(d/g) (about 1/28 of a contact).
// The gate follows the scene's valve: after the dead time it opens the slot at a constant stroke
// speed, the open width being the width of the round bore's open area (model/bore_area.hpp), and
// closes the same way after the close command.
#include <cstdint>
#include <functional>
#include <vector>

#include "dynweigh/granular/dem_contact_parameters.hpp"
#include "dynweigh/granular/outflow_profile.hpp"

namespace dynweigh::granular {

struct DemSceneConfig {
  // The scene (SI).
  double bore_m = 0.060;
  double fall_height_m = 1.200;        // orifice plane to the container floor
  double container_width_m = 0.300;
  double bulk_density = 1550.0;        // kg/m^3
  double gravity = 9.81;
  double valve_dead_time_s = 0.030;
  double valve_full_stroke_s = 0.080;
  // The schedule: open command at t = 0, close command at close_s; the run ends settle_s after
  // the last grain can have landed.
  double close_s = 0.5;
  double settle_s = 0.35;
  // Scaling (see above).
  double discs_across_orifice = 8.0;
  double silo_width_bores = 4.0;
  int fill_discs = 1200;
  double packing_fraction_2d = 0.83;   // random packing of near-monodisperse discs
  bool with_container = true;          // false: a silo-only discharge (Beverloo sweeps)
  // Contact model in reduced units (d, mean disc mass, sqrt(d/g)).
  ContactParameters reduced_contact;
  double reduced_time_step = 5e-4;
  double settle_reduced_time_max = 40.0;  // closed-silo settling, ends earlier once at rest
  // Output.
  double sample_period_s = 0.001;
  int profile_bins = 16;
};

struct DemSceneRun {
  // One row per sample period: the period's end, the mean force on the container over it
  // (floor and walls, downward positive, N), and the mass that has left the silo (centres
  // below the bottom discs' centres).
  std::vector<double> time_s, force_n, released_kg;
  OutflowSummary outflow;          // across the slot while the gate is fully open
  double grain_diameter_m = 0;     // d
  double disc_mass_kg = 0;         // of a disc of diameter d
  double slot_depth_m = 0;
  double bed_bulk_density = 0;     // measured in the settled silo
  double released_total_kg = 0;
  double lost_kg = 0;              // discs that left the box (bounced out of the container)
  double settle_s = 0;             // simulated time of the closed-silo settling
  std::int64_t discs = 0;
  std::int64_t steps = 0;
  double particle_steps = 0;
  double cpu_seconds = 0;          // of the calling thread
};

// One DEM run of the scene: a pure function of (config, seed); `progress` (may be empty) gets
// the fraction done now and then.
DemSceneRun run_dem_scene(const DemSceneConfig& config, std::uint64_t seed,
                          const std::function<void(double)>& progress = {});

// The steady discharge rate (kg/s) of a run: least squares slope of released_kg over
// [from_s, to_s].
double steady_discharge_kg_s(const DemSceneRun& run, double from_s, double to_s);

}  // namespace dynweigh::granular
