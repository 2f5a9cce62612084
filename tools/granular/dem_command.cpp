// dynweigh dem: the 2D DEM silo of the peer inputs (thesis section 3.4), discharge rate, speed,
// and the force on the bottom (the scale) every step.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>

#include "command_line_errors.hpp"
#include "dynweigh/granular/silo2d.hpp"
#include "granular_commands.hpp"

namespace dynweigh::tools {

using namespace dynweigh::granular;

int run_dem_command(int argc, char** argv) {
  CLI::App app{"2D DEM (thesis section 3.4): the peer's 2D silo in reduced units (d = 1, g = 1); rates in discs per sqrt(d/g)"};
  std::string scene;
  bool silo2d = false;
  int orifice = 8;
  int particles = 3612;
  long long steps = 600000;
  long long fill_steps = 120000;
  long long sample_every = 2000;
  unsigned long long seed = 58271;
  double container_drop = 0;
  std::string csv;
  app.add_option("--scene", scene, "built-in scene: silo2d (the peer silo)")->check(CLI::IsMember({"silo2d"}));
  app.add_flag("--silo2d", silo2d, "the peer's 2D flat-bottom silo");
  app.add_option("--orifice", orifice, "orifice width D in disc diameters (bottom discs removed)")->check(CLI::Range(1, 40));
  app.add_option("--particles", particles, "moving discs (peer: 3612)")->check(CLI::Range(1, 10000000));
  app.add_option("--steps", steps, "discharge steps at most (stops earlier when 36 % of the discs left)")->check(CLI::NonNegativeNumber);
  app.add_option("--fill-steps", fill_steps, "settling steps with the orifice closed (peer: 120000)")->check(CLI::NonNegativeNumber);
  app.add_option("--sample-every", sample_every, "steps between counts of the discs left")->check(CLI::PositiveNumber);
  app.add_option("--seed", seed, "seed of the disc diameters");
  app.add_option("--container-drop", container_drop, "put a container bottom (the scale) this far below the orifice")->check(CLI::NonNegativeNumber);
  app.add_option("--csv", csv, "write step,time,discs_above,silo_bottom_force_y,container_force_y every step");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return report_parse_outcome(app, e, "dem");
  }
  if (!silo2d && scene.empty()) return fail("dem", "give --silo2d or --scene NAME");
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
  const auto fill_start = std::chrono::steady_clock::now();
  double fill_particle_steps = 0;
  for (long long s = 0; s < fill_steps; ++s) {
    world.step();
    fill_particle_steps += static_cast<double>(world.size());
  }
  const double fill_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - fill_start).count();
  open_silo2d_orifice(world, config, orifice);

  // Discharge: the peer stops when fewer than 2300 of its 3612 discs are above the bottom.
  const auto stop_below = static_cast<std::size_t>(static_cast<double>(world.count_moving_above(0.5)) * 2300.0 / 3612.0);
  const std::size_t container_wall = world.wall_count() - 1;
  DischargeResult result;
  result.samples.push_back({world.time(), world.count_moving_above(0.5)});
  const auto start = std::chrono::steady_clock::now();
  long long done = 0;
  while (done < steps) {
    world.step();
    ++done;
    result.particle_steps += static_cast<double>(world.size());
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
  result.steps = done;
  fit_discharge_rates(result, 0.1);
  std::printf("scene=silo2d\norifice=%d\nparticles=%d\nfill_steps=%lld\nfill_particle_steps_per_s=%.4g\nsteps=%lld\n"
              "particles_left=%zu\nparticle_steps_per_s=%.4g\ndischarge_rate=%.4f\ndischarge_rate_first_half=%.4f\n"
              "discharge_rate_second_half=%.4f\nseconds=%.3f\n",
              orifice, particles, fill_steps, fill_seconds > 0 ? fill_particle_steps / fill_seconds : 0.0, done,
              world.moving_count(), seconds > 0 ? result.particle_steps / seconds : 0.0,
              result.rate, result.rate_first_half, result.rate_second_half, seconds);
  return 0;
}

}  // namespace dynweigh::tools
