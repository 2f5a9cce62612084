// dynweigh dem: the 2D DEM silo of the peer inputs (thesis section 3.4), discharge rate, speed,
// and the force on the bottom (the scale) every step.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <fstream>
#include <optional>
#include <cmath>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "dynweigh/granular/dem_calibration.hpp"
#include "dynweigh/granular/impact_relaxation_estimate.hpp"
#include "dynweigh/granular/outflow_profile.hpp"
#include "dynweigh/granular/silo2d.hpp"
#include "dynweigh/sim/scene.hpp"
#include "granular_commands.hpp"
#include "progress_bar.hpp"

namespace dynweigh::tools {

using namespace dynweigh::granular;

namespace {

struct SceneDoseOptions {
  std::string scene;
  double close_s = 0.8;
  double discs_across = 8.0;
  int particles = 1200;
  unsigned long long seed = 1;
  std::string csv;
  bool quiet = false;
};

// `dem --scene NAME`: the scene's silo, gate, fall and container as a 2D DEM (dem_scene.hpp says
// how it is scaled); the force on the container bottom over time, as the lumped plant gives it.
int run_scene_dose(const SceneDoseOptions& o) {
  std::optional<sim::Scene> scene;
  try {
    scene = sim::scene_by_name(o.scene);
  } catch (const std::exception& e) {
    return fail("dem", e.what());
  }
  if (!scene) return fail("dem", "unknown scene '" + o.scene + "' (see dynweigh sim --list; or silo2d)");
  std::ofstream out;
  if (!o.csv.empty()) {
    out.open(o.csv);
    if (!out) return fail("dem", "cannot write " + o.csv);
  }
  DemSceneConfig config = dem_scene_config(*scene, o.close_s, o.discs_across);
  config.fill_discs = o.particles;
  ProgressBar bar("dem " + o.scene, 1000, !o.quiet);
  DemSceneRun run;
  try {
    run = run_dem_scene(config, o.seed, [&](double f) { bar.update(static_cast<std::uint64_t>(1000 * f)); });
  } catch (const std::exception& e) {
    return fail("dem", e.what());
  }
  bar.finish();
  if (out) {
    out << "t_s,force_n,released_kg\n";
    for (std::size_t k = 0; k < run.time_s.size(); ++k) {
      out << run.time_s[k] << ',' << run.force_n[k] << ',' << run.released_kg[k] << '\n';
    }
  }
  const double steady_from = config.valve_dead_time_s + config.valve_full_stroke_s + 0.1;
  const ForceSignalFeatures f = force_signal_features(run.time_s, run.force_n, steady_landing_end_s(config));
  std::printf("scene=%s\nmodel=dem2d\nseed=%llu\ngrain_d_m=%.5g\nslot_depth_m=%.5g\ndisc_mass_kg=%.5g\nparticles=%lld\n"
              "settle_s=%.4f\nsteps=%lld\nparticle_steps=%.6g\ncpu_seconds=%.3f\nparticle_steps_per_cpu_s=%.4g\n",
              scene->name.c_str(), o.seed, run.grain_diameter_m, run.slot_depth_m, run.disc_mass_kg,
              static_cast<long long>(run.discs), run.settle_s, static_cast<long long>(run.steps), run.particle_steps,
              run.cpu_seconds, run.cpu_seconds > 0 ? run.particle_steps / run.cpu_seconds : 0.0);
  std::printf("close_s=%.4f\nbed_bulk_density=%.5g\ndischarge_rate_kg_s=%.5g\noutflow_alpha=%.4f\nreleased_kg=%.5g\n"
              "lost_kg=%.4g\ndead_time_s=%.4f\nimpulse_n=%.5g\nslope_n_s=%.5g\nrelaxation_estimate_s=%.4f\n"
              "final_force_n=%.5g\n",
              o.close_s, run.bed_bulk_density, steady_discharge_kg_s(run, steady_from, o.close_s + config.valve_dead_time_s),
              run.outflow.alpha, run.released_total_kg, run.lost_kg, f.dead_time_s, f.impulse_n, f.slope_n_s,
              f.relaxation_s, f.final_n);
  std::printf("lumped_equivalent=dynweigh sim --scene %s --schedule open@0,close@%ld --duration %.3f --csv FILE\n",
              o.scene.c_str(), std::lround(o.close_s / 0.01), run.time_s.empty() ? 0.0 : run.time_s.back());
  if (out) std::printf("csv=%s\n", o.csv.c_str());
  return 0;
}

}  // namespace

int run_dem_command(int argc, char** argv) {
  CLI::App app{"2D DEM (thesis section 3.4): the peer's 2D silo in reduced units (d = 1, g = 1); rates in discs per sqrt(d/g)"};
  std::string scene;
  bool silo2d = false;
  int orifice = 8;
  int particles = 3612;
  long long steps = 600000;
  long long fill_steps = 120000;
  long long sample_every = 2000;
  bool quiet = false;
  unsigned long long seed = 58271;
  double container_drop = 0;
  long long stop_below_option = -1;
  bool no_calibration = false;
  int calibration_every = 20;
  std::string csv;
  app.add_option("--scene", scene, "a plant scene (name or .json) as a 2D DEM dose, or silo2d (the peer silo)");
  double close_s = 0.8;
  double discs_across = 8.0;
  app.add_option("--close", close_s, "--scene: close command time in s (open command at 0)")->check(CLI::Range(0.05, 30.0));
  app.add_option("--discs-across", discs_across, "--scene: discs across the bore (coarse graining: d = bore / this)")
      ->check(CLI::Range(2.0, 60.0));
  app.add_flag("--silo2d", silo2d, "the peer's 2D flat-bottom silo");
  app.add_option("--orifice", orifice, "orifice width D in disc diameters (bottom discs removed)")->check(CLI::Range(1, 40));
  app.add_option("--particles", particles, "moving discs (peer: 3612)")->check(CLI::Range(1, 10000000));
  app.add_option("--steps", steps, "discharge steps at most (stops earlier when 36 % of the discs left)")->check(CLI::NonNegativeNumber);
  app.add_option("--fill-steps", fill_steps, "settling steps with the orifice closed (peer: 120000)")->check(CLI::NonNegativeNumber);
  app.add_option("--stop-below", stop_below_option, "stop when fewer discs than this are above the bottom (peer: 2300; default 2300/3612 of the fill)")->check(CLI::NonNegativeNumber);
  app.add_flag("--quiet", quiet, "no progress bar");
  app.add_option("--sample-every", sample_every, "steps between counts of the discs left")->check(CLI::PositiveNumber);
  app.add_option("--seed", seed, "seed of the disc diameters");
  app.add_option("--container-drop", container_drop, "put a container bottom (the scale) this far below the orifice")->check(CLI::NonNegativeNumber);
  app.add_flag("--no-calibration", no_calibration, "skip the calibration measurements (alpha, impact relaxation) for pure speed runs");
  app.add_option("--calibration-every", calibration_every, "steps between samples of the outflow speed profile")->check(CLI::PositiveNumber);
  app.add_option("--csv", csv, "write step,time,discs_above,silo_bottom_force_y,container_force_y every step");
  if (const auto exit_status = tools::parse_command_line(app, argc, argv, "dynweigh dem")) return *exit_status;
  if (!silo2d && scene.empty()) return fail("dem", "give --silo2d or --scene NAME");
  if (!silo2d && scene != "silo2d") {
    SceneDoseOptions o;
    o.scene = scene;
    o.close_s = close_s;
    o.discs_across = discs_across;
    if (app.count("--particles") > 0) o.particles = particles;
    o.seed = app.count("--seed") > 0 ? seed : 1;
    o.csv = csv;
    o.quiet = quiet;
    return run_scene_dose(o);
  }
  Silo2dConfig config;
  config.moving_discs = particles;
  config.seed = seed;
  config.container_drop = container_drop;
  // The lattice is 43 discs wide; more discs stack higher, so raise the box to hold them.
  const double rows = static_cast<double>(particles) / 43.0 + 1.0;
  if (config.fill_min_y + rows * config.lattice_spacing > config.box_top - 2) config.box_top = config.fill_min_y + rows * config.lattice_spacing + 5;
  std::ofstream out;
  if (!csv.empty()) {
    out.open(csv);
    if (!out) return fail("dem", "cannot write " + csv);
    out << "step,time,discs_above,silo_bottom_force_y,container_force_y\n";
  }
  Dem2dWorld world = make_silo2d(config);
  // Wall-clock and process CPU time: on a shared machine the CPU time is the fairer measure of
  // speed (compare_lammps.sh takes LAMMPS' CPU time the same way).
  const std::clock_t fill_cpu_start = std::clock();
  const auto fill_start = std::chrono::steady_clock::now();
  double fill_particle_steps = 0;
  dynweigh::tools::ProgressBar bar("dem", static_cast<std::uint64_t>(fill_steps + steps), !quiet);
  constexpr long long kProgressEvery = 1024;  // the bar reads the clock; not every step
  for (long long s = 0; s < fill_steps; ++s) {
    if (s % kProgressEvery == 0) bar.update(static_cast<std::uint64_t>(s));
    world.step();
    fill_particle_steps += static_cast<double>(world.size());
  }
  const double fill_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - fill_start).count();
  const double fill_cpu_seconds = static_cast<double>(std::clock() - fill_cpu_start) / CLOCKS_PER_SEC;
  const std::int64_t fill_rebuilds = world.list_rebuilds();
  open_silo2d_orifice(world, config, orifice);

  // Discharge: the peer stops when fewer than 2300 of its 3612 discs are above the bottom.
  const auto stop_below = stop_below_option >= 0 ? static_cast<std::size_t>(stop_below_option)
                                                 : static_cast<std::size_t>(static_cast<double>(world.count_moving_above(0.5)) * 2300.0 / 3612.0);
  const std::size_t container_wall = world.wall_count() - 1;
  // Calibration of the lumped plant: the outflow speed profile across the orifice (alpha) and,
  // with a container, its load after the stream lands (impact relaxation time).
  OutflowProfile outflow = make_silo2d_outflow_profile(config.width, orifice, std::max(4, 2 * orifice));
  std::vector<double> load_time, load;
  if (!no_calibration && container_drop > 0) {
    const auto expected = static_cast<std::size_t>(std::min(steps, 1LL << 22));  // grows beyond, if asked
    load_time.reserve(expected);
    load.reserve(expected);
  }
  DischargeResult result;
  result.samples.push_back({world.time(), world.count_moving_above(0.5)});
  const std::clock_t cpu_start = std::clock();
  const auto start = std::chrono::steady_clock::now();
  long long done = 0;
  while (done < steps) {
    if (done % kProgressEvery == 0) bar.update(static_cast<std::uint64_t>(fill_steps + done));
    world.step();
    ++done;
    result.particle_steps += static_cast<double>(world.size());
    if (!no_calibration) {
      if (done % calibration_every == 0) sample_outflow(outflow, world);
      if (container_drop > 0) {
        load_time.push_back(world.time());
        load.push_back(-world.wall_force(container_wall).y);
      }
    }
    if (out) {
      const double container = container_drop > 0 ? world.wall_force(container_wall).y : 0.0;
      out << done << ',' << world.time() << ',' << (done % sample_every == 0 ? std::to_string(world.count_moving_above(0.5)) : "")
          << ',' << world.fixed_disc_force().y << ',' << container << '\n';
    }
    if (done % sample_every == 0) {
      const std::size_t above = world.count_moving_above(0.5);
      result.samples.push_back({world.time(), above});
      if (above < stop_below) break;
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double cpu_seconds = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  result.steps = done;
  fit_discharge_rates(result, 0.1);
  const auto rate_of = [](double work, double time) { return time > 0 ? work / time : 0.0; };
  bar.finish();
  std::printf("scene=silo2d\norifice=%d\nparticles=%d\nfill_steps=%lld\nfill_particle_steps=%.6g\n"
              "fill_seconds=%.3f\nfill_cpu_seconds=%.3f\nfill_particle_steps_per_s=%.4g\nfill_particle_steps_per_cpu_s=%.4g\n"
              "fill_list_rebuilds=%lld\n",
              orifice, particles, fill_steps, fill_particle_steps, fill_seconds, fill_cpu_seconds,
              rate_of(fill_particle_steps, fill_seconds), rate_of(fill_particle_steps, fill_cpu_seconds),
              static_cast<long long>(fill_rebuilds));
  std::printf("steps=%lld\nparticles_left=%zu\nparticle_steps=%.6g\nseconds=%.3f\ncpu_seconds=%.3f\n"
              "particle_steps_per_s=%.4g\nparticle_steps_per_cpu_s=%.4g\nlist_rebuilds=%lld\n"
              "discharge_rate=%.4f\ndischarge_rate_first_half=%.4f\ndischarge_rate_second_half=%.4f\n",
              done, world.moving_count(), result.particle_steps, seconds, cpu_seconds,
              rate_of(result.particle_steps, seconds), rate_of(result.particle_steps, cpu_seconds),
              static_cast<long long>(world.list_rebuilds() - fill_rebuilds), result.rate, result.rate_first_half,
              result.rate_second_half);
  if (!no_calibration) {
    const OutflowSummary o = summarize_outflow(outflow);
    std::printf("outflow_alpha=%.4f\noutflow_mean_speed=%.4f\noutflow_peak_speed=%.4f\noutflow_sampled_discs=%.0f\n", o.alpha,
                o.mean_speed, o.peak_speed, o.sampled_discs);
    if (container_drop > 0) {
      const ImpactRelaxationEstimate e = estimate_impact_relaxation(load_time, load);
      std::printf("impact_valid=%d\nimpact_landing_time=%.4f\nimpact_step_force=%.4f\nimpact_load_slope=%.4f\n"
                  "impact_relaxation_time=%.4f\n",
                  e.valid ? 1 : 0, e.landing_time, e.step_force, e.load_slope, e.relaxation_time);
    }
  }
  return 0;
}

}  // namespace dynweigh::tools
