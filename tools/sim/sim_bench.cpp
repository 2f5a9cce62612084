// dynweigh bench --sim: for each shipped scene, simulated seconds per wall second on one core
// for the standard test cycle (starttestdata 50 600, 10 s), and the error of its final reading
// against the same scene and seed run at a 10x finer internal step.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "dynweigh/sim/scene_file.hpp"
#include "dynweigh/sim/valve_schedule.hpp"
#include "sim_commands.hpp"
#include "command_line.hpp"

namespace {

using namespace dynweigh;

struct CycleResult {
  double final_reading_kg;
  std::uint64_t steps;
  long long raw_sum;  // keeps the samples alive against the optimiser
};

CycleResult run_cycle(const sim::Scene& scene, std::uint64_t seed, const std::vector<sim::ScheduledCommand>& schedule,
                      std::uint32_t jiffies) {
  sim::Plant plant(scene, seed);
  long long raw_sum = 0;
  sim::run_valve_schedule(plant, schedule, jiffies, [&](const sim::JiffyRecord& r) { raw_sum += r.sample.raw_counts; });
  return {plant.truth().force_n / scene.g, plant.steps(), raw_sum};
}

}  // namespace

int run_sim_bench(int argc, char** argv) {
  CLI::App app{"Plant speed and accuracy per shipped scene: one line per scene,\n"
               "scene=<name> realtime_factor=<x> final_error_kg=<e> steps=<n>",
               "dynweigh bench --sim"};
  std::vector<std::string> scenes;
  std::string schedule_text = "open@50,close@600";
  double cycle_s = 10.0;
  double min_wall_s = 0.3;
  std::uint64_t seed = 1;
  bool sim_flag = false;
  app.add_flag("--sim", sim_flag, "benchmark the plant simulator (this benchmark)");
  app.add_option("--scene", scenes, "scenes to run (default: every shipped scene)");
  app.add_option("--schedule", schedule_text, "valve events in jiffies")->capture_default_str();
  app.add_option("--cycle", cycle_s, "simulated seconds per cycle")->capture_default_str()->check(CLI::Range(0.01, 1e5));
  app.add_option("--min-time", min_wall_s, "wall seconds to repeat each scene for")->capture_default_str()->check(CLI::Range(0.0, 600.0));
  app.add_option("--seed", seed, "seed")->capture_default_str();
  if (const auto exit_status = tools::parse_command_line(app, argc, argv, "dynweigh bench")) return *exit_status;
  try {
    if (scenes.empty()) scenes = sim::scene_names();
    const auto schedule = sim::parse_valve_schedule(schedule_text);
    const auto jiffies = static_cast<std::uint32_t>(std::llround(cycle_s / sim::kJiffyS));
    for (const std::string& name : scenes) {
      const std::optional<sim::Scene> scene = sim::scene_by_name(name);
      if (!scene) {
        std::fprintf(stderr, "dynweigh bench: unknown scene '%s'\n", name.c_str());
        return 2;
      }
      using Clock = std::chrono::steady_clock;
      const auto started = Clock::now();
      CycleResult result{};
      int runs = 0;
      double wall_s = 0.0;
      do {
        result = run_cycle(*scene, seed, schedule, jiffies);
        ++runs;
        wall_s = std::chrono::duration<double>(Clock::now() - started).count();
      } while (wall_s < min_wall_s || runs < 3);
      sim::Scene fine = *scene;
      fine.internal_step_s = scene->internal_step_s / 10.0;
      const CycleResult reference = run_cycle(fine, seed, schedule, jiffies);
      std::printf("scene=%s realtime_factor=%.0f final_error_kg=%.3g steps=%llu\n", name.c_str(),
                  cycle_s * runs / wall_s, std::abs(result.final_reading_kg - reference.final_reading_kg),
                  static_cast<unsigned long long>(result.steps));
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dynweigh bench: %s\n", e.what());
    return 2;
  }
}
