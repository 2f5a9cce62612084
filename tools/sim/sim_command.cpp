// dynweigh sim --scene NAME --schedule open@50,close@600 --duration 10 --csv out.csv
// dynweigh sim --scene NAME --describe
#include <cmath>
#include <cstdio>
#include <exception>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "dynweigh/sim/scene_file.hpp"
#include "dynweigh/sim/valve_schedule.hpp"
#include "finite_range.hpp"
#include "sim_commands.hpp"
#include "trace_csv.hpp"
#include "command_line.hpp"

namespace {

using namespace dynweigh;

int fail(const std::string& message) {
  std::fprintf(stderr, "dynweigh sim: %s\n", message.c_str());
  return 2;
}

std::string scene_list() {
  std::string names;
  for (const std::string& name : sim::scene_names()) names += (names.empty() ? "" : ", ") + name;
  return names;
}

}  // namespace

int run_sim_command(int argc, char** argv) {
  CLI::App app{"Run a plant scene open-loop with a valve schedule and write the cycle CSV (docs/programs.md).\n"
               "Scenes: built-in default and ideal, and <name>.json in the scenes folder: $DYNWEIGH_SCENES, else\n"
               "the installed ../share/dynweigh/scenes beside the program, else the source tree's scenes/.",
               "dynweigh sim"};
  std::string scene_name = "default";
  std::string schedule_text = "open@50,close@600";
  double duration_s = 10.0;
  std::string csv_path;
  std::uint64_t seed = 1;
  double step_s = 0.0;
  bool describe = false;
  bool list = false;
  app.add_option("--scene", scene_name, "scene name or path to a .json scene file")->capture_default_str();
  app.add_option("--schedule", schedule_text, "valve events in jiffies: open@N, half@N, close@N, comma-separated")
      ->capture_default_str();
  app.add_option("--duration", duration_s, "simulated seconds")->capture_default_str()->check(tools::FiniteRange(0.0, 1e7));
  app.add_option("--csv", csv_path, "write one row per jiffy: t_s,jiffy,static_kg,in_flight_kg,force_n,raw,filtered_g,valve");
  app.add_option("--seed", seed, "seed of the plant's disturbances")->capture_default_str();
  app.add_option("--step", step_s, "override the scene's internal step in seconds (must divide 10 ms)")
      ->check(tools::FiniteRange(1e-7, 0.01));
  app.add_flag("--describe", describe, "print the scene's resolved parameters as key=value lines and exit");
  app.add_flag("--list", list, "print the scene names and exit");
  if (const auto exit_status = tools::parse_command_line(app, argc, argv, "dynweigh sim")) return *exit_status;

  try {
    if (list) {
      for (const std::string& name : sim::scene_names()) std::printf("%s\n", name.c_str());
      return 0;
    }
    std::optional<sim::Scene> scene = sim::scene_by_name(scene_name);
    if (!scene) return fail("unknown scene '" + scene_name + "' (known: " + scene_list() + ")");
    if (step_s > 0.0) {
      scene->internal_step_s = step_s;
      sim::validate_scene(*scene, "--step");
    }
    if (describe) {
      for (const auto& [key, value] : sim::describe_scene(*scene)) std::printf("%s=%s\n", key.c_str(), value.c_str());
      return 0;
    }
    const auto schedule = sim::parse_valve_schedule(schedule_text);
    const auto jiffies = static_cast<std::uint32_t>(std::llround(duration_s / sim::kJiffyS));

    std::unique_ptr<tools::TraceCsv> csv;
    if (!csv_path.empty()) csv = std::make_unique<tools::TraceCsv>(csv_path);
    sim::Plant plant(*scene, seed);
    sim::run_valve_schedule(plant, schedule, jiffies, [&](const sim::JiffyRecord& r) {
      if (!csv) return;
      hal::host::TraceRow row;
      row.t_s = r.truth.time_s;
      row.jiffy = r.jiffy;
      row.static_kg = r.truth.static_kg;
      row.in_flight_kg = r.truth.in_flight_kg;
      row.force_n = r.truth.force_n;
      row.raw = r.sample.raw_counts;
      row.valve = static_cast<int>(r.command);
      row.has_filtered = false;
      csv->write(row);
    });
    const sim::PlantTruth& t = plant.truth();
    std::printf("scene=%s\nseed=%llu\nduration_s=%.3f\njiffies=%u\nsteps=%llu\n", scene->name.c_str(),
                static_cast<unsigned long long>(seed), t.time_s, jiffies, static_cast<unsigned long long>(plant.steps()));
    std::printf("released_kg=%.6f\nstatic_kg=%.6f\nin_flight_kg=%.6f\nsilo_kg=%.6f\n", t.released_kg, t.static_kg,
                t.in_flight_kg, t.silo_kg);
    std::printf("final_force_n=%.6f\nfinal_reading_kg=%.6f\navalanches=%llu\ncomponents=%s\n", t.force_n,
                t.force_n / scene->g, static_cast<unsigned long long>(t.avalanches), plant.components().names().c_str());
    if (csv) std::printf("csv=%s\n", csv_path.c_str());
    return 0;
  } catch (const std::exception& e) {
    return fail(e.what());
  }
}
