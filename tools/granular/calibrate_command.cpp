// dynweigh calibrate --from dem|soc|fluid --scene NAME [--out FILE]: runs a detail model of the
// scene and writes the lumped parameters it gives into a scene file.
// The DEM runs are the jobs of a scenario grid (tools/grid): threads, or MPI ranks under mpirun,
// journalled for --resume; each run is seeded by its job (the dose's seed, the sweep width's seed),
// never by a rank or a thread, so every way of running it writes the same scene.
#include <CLI/CLI.hpp>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "output_file.hpp"
#include "dem_job_row.hpp"
#include "dynweigh/granular/dem_calibration.hpp"
#include "dynweigh/granular/soc_fluid_calibration.hpp"
#include "dynweigh/sim/scene_file.hpp"
#include "granular_commands.hpp"
#include "grid_runner.hpp"
#include "progress_bar.hpp"

namespace dynweigh::tools {

using namespace dynweigh::granular;

namespace {

struct CalibrateOptions {
  std::string from;
  std::string scene = "default";
  std::string out;
  std::string name;
  std::string csv;
  std::string journal;
  bool resume = false;
  unsigned long long seed = 1;
  int seeds = 3;
  int jobs = 1;
  bool quiet = false;
  bool compare = false;
  DemCalibrationOptions dem;
  bool no_sweep = false;
  long long grains = 200000;
  long long large_size = 0;
  int critical_step = 1;
  int grid = 257;
};

void print_kv(const char* key, double value) { std::printf("%s=%.6g\n", key, value); }

int write_scene(const CalibrateOptions& o, sim::Scene scene, const std::string& notes) {
  if (o.out.empty()) return 0;
  if (!o.name.empty()) {
    scene.name = o.name;
  } else {
    const std::size_t slash = o.out.find_last_of('/');
    std::string stem = o.out.substr(slash == std::string::npos ? 0 : slash + 1);
    if (stem.size() > 5 && stem.compare(stem.size() - 5, 5, ".json") == 0) stem.resize(stem.size() - 5);
    scene.name = stem;
  }
  scene.source += "; calibrated by dynweigh calibrate --from " + o.from;
  sim::validate_scene(scene, o.out);
  std::ofstream file(o.out);
  if (!file) return fail("calibrate", "cannot write " + o.out);
  file << sim::scene_to_json(scene, notes);
  std::printf("out=%s\n", o.out.c_str());
  return 0;
}

// What decides a DEM row besides its key: the scene (its name and a hash of all its parameters)
// and the options every job shares. A resume refuses a journal written with other ones.
std::string dem_grid_signature(const sim::Scene& base, const DemCalibrationOptions& options) {
  std::uint64_t hash = 14695981039346656037ull;  // FNV-1a
  for (const unsigned char c : sim::scene_to_json(base)) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  char text[320];
  std::snprintf(text, sizeof text,
                "calibrate dem scene=%s scene_hash=%016llx close_s=%.17g discs_across=%.17g particles=%d "
                "sweep_close_s=%.17g",
                base.name.c_str(), static_cast<unsigned long long>(hash), options.close_s,
                options.discs_across_orifice, options.fill_discs, options.sweep_close_s);
  return text;
}

// The DEM jobs through the grid runner; the results in the jobs' order on the writer, none on
// the other ranks.
std::vector<DemJobResult> run_dem_grid(const CalibrateOptions& o, const sim::Scene& base,
                                       const std::vector<DemJob>& jobs, const DemCalibrationOptions& options,
                                       const grid::ParallelSession& session) {
  std::vector<std::string> keys;
  for (const DemJob& job : jobs) keys.push_back(dem_job_key(job));
  ProgressBar bar("calibrate dem", jobs.size(), !o.quiet && session.writer());
  grid::GridOptions grid_options;
  grid_options.threads = static_cast<unsigned>(o.jobs);
  grid_options.journal_path = o.journal;
  grid_options.resume = o.resume;
  grid_options.signature = dem_grid_signature(base, options);
  grid_options.progress = [&bar](std::size_t finished, std::size_t) { bar.update(finished); };
  const grid::GridOutcome outcome = grid::run_grid(
      session, keys, [&](std::size_t i) { return encode_dem_job_row(run_dem_job(jobs[i])); }, grid_options);
  bar.finish();
  std::vector<DemJobResult> results;
  if (!session.writer()) return results;
  for (std::size_t i = 0; i < jobs.size(); ++i) results.push_back(decode_dem_job_row(jobs[i], outcome.rows[i]));
  if (!o.journal.empty() || session.distributed()) grid::report_grid(outcome, session, o.journal);
  return results;
}

int calibrate_dem(const CalibrateOptions& o, const sim::Scene& base) {
  DemCalibrationOptions options = o.dem;
  options.seeds.clear();
  for (int k = 0; k < o.seeds; ++k) options.seeds.push_back(o.seed + static_cast<unsigned long long>(k));
  if (o.no_sweep) options.sweep_orifices.clear();
  const std::vector<DemJob> jobs = dem_calibration_jobs(base, options);
  const grid::ParallelSession session(true);
  std::vector<DemJobResult> results;
  try {
    results = run_dem_grid(o, base, jobs, options, session);
  } catch (const std::exception& e) {
    fail("calibrate", e.what());
    if (session.distributed()) session.abort(1);  // the other ranks would wait for jobs forever
    return 1;
  }
  if (!session.writer()) return 0;
  const DemCalibration c = calibrate_from_dem(base, results, options);
  std::printf("scene=%s\nfrom=dem\njobs=%zu\ndoses=%zu\ngrain_d_m=%.5g\n", base.name.c_str(), jobs.size(), c.doses,
              c.grain_diameter_m);
  for (std::size_t k = 0; k < c.sweep_orifice_m.size(); ++k) {
    std::printf("sweep_orifice_m=%.5g rate_per_depth_kg_s_m=%.5g\n", c.sweep_orifice_m[k], c.sweep_rate_per_depth[k]);
  }
  print_kv("dem_rate_kg_s", c.dem_rate_kg_s);
  print_kv("beverloo_k", c.beverloo_k);
  print_kv("beverloo_C", c.beverloo_c);
  print_kv("beverloo_C_2d", c.beverloo_c_2d);
  print_kv("beverloo_worst_residual", c.beverloo_worst_residual);
  print_kv("flow_factor", c.flow_factor.mean);
  print_kv("flow_factor_standard_error", c.flow_factor.standard_error);
  print_kv("alpha_start", c.alpha_start);
  print_kv("alpha_settle_s", c.alpha_settle_s);
  print_kv("released_fit_rms_kg", c.released_fit_rms_kg);
  print_kv("dem_relaxation_estimate_s", c.dem_relaxation_estimate_s.mean);
  print_kv("dem_relaxation_estimate_standard_error_s", c.dem_relaxation_estimate_s.standard_error);
  print_kv("impact_relaxation_s", c.scene.impact.relaxation_s);
  print_kv("impact_relaxation_standard_error_s", c.relaxation_s.standard_error);
  print_kv("dem_dead_time_s", c.dead_time_s.mean);
  print_kv("dem_dead_time_standard_error_s", c.dead_time_s.standard_error);
  print_kv("dem_impulse_n", c.impulse_n.mean);
  print_kv("dem_impulse_standard_error_n", c.impulse_n.standard_error);
  print_kv("dem_slope_n_s", c.slope_n_s.mean);
  print_kv("dem_slope_standard_error_n_s", c.slope_n_s.standard_error);
  print_kv("dem_final_n", c.final_n.mean);
  print_kv("dem_bed_bulk_density", c.bed_bulk_density);
  print_kv("dem_cpu_seconds_per_dose", c.dem_cpu_seconds_per_dose);
  if (o.compare || !o.csv.empty()) {
    const std::vector<ModelComparison> rows = compare_with_dem(base, c, results, options);
    std::printf("| model | CPU s per run | dead time error ms | impulse error %% | slope error %% | final error %% | rms error N (10 ms means) |\n");
    std::printf("| --- | --- | --- | --- | --- | --- | --- |\n");
    for (const ModelComparison& r : rows) {
      std::printf("| %s | %.4g | %.1f | %.1f | %.1f | %.2f | %.2f |\n", r.model.c_str(), r.cpu_seconds_per_run,
                  1e3 * r.dead_time_error_s, 100 * r.impulse_error, 100 * r.slope_error, 100 * r.final_error,
                  r.signal_rms_error_n);
    }
    for (const ModelComparison& r : rows) {
      std::printf("compare_%s=cpu_s:%.4g dead_time_s:%.4f impulse_n:%.4g slope_n_s:%.4g final_n:%.4g\n", r.model.c_str(),
                  r.cpu_seconds_per_run, r.features.dead_time_s, r.features.impulse_n, r.features.slope_n_s,
                  r.features.final_n);
    }
    if (rows.size() >= 3 && rows[2].cpu_seconds_per_run > 0) {
      print_kv("cost_ratio_dem_dose_to_lumped", rows[0].cpu_seconds_per_run / rows[2].cpu_seconds_per_run);
    }
  }
  if (!o.csv.empty()) {
    const LumpedDose dem = mean_dem_signal(results);
    const double period = dem.time_s[1] - dem.time_s[0];
    const LumpedDose lumped = run_lumped_dose(rigid_scale_scene(c.scene), options.close_s, dem.time_s.back(), period, o.seed);
    std::ofstream file(o.csv);
    if (!file) return fail("calibrate", "cannot write " + o.csv);
    file << "t_s,dem_force_n,lumped_force_n,dem_released_kg,lumped_released_kg\n";
    for (std::size_t k = 0; k < dem.time_s.size() && k < lumped.time_s.size(); ++k) {
      file << dem.time_s[k] << ',' << dem.force_n[k] << ',' << lumped.force_n[k] << ',' << dem.released_kg[k] << ','
           << lumped.released_kg[k] << '\n';
    }
    std::printf("csv=%s\n", o.csv.c_str());
  }
  return write_scene(o, c.scene, dem_calibration_notes(c, options));
}

int calibrate_soc(const CalibrateOptions& o, const sim::Scene& base) {
  const SocSceneCalibration c = calibrate_from_soc(base, o.grains, o.large_size, o.critical_step, o.seed);
  std::printf("scene=%s\nfrom=soc\ncolumns=%lld\ngrains=%lld\ncell_mass_kg=%.5g\nlarge_avalanches=%lld\n", base.name.c_str(),
              static_cast<long long>(c.columns), static_cast<long long>(c.grains), c.cell_mass_kg,
              static_cast<long long>(c.large_avalanches));
  print_kv("avalanche_critical_kg", c.critical_kg);
  print_kv("avalanche_force_n", c.force_n);
  print_kv("avalanche_duration_s", c.duration_s);
  print_kv("pile_height_exponent", c.height_exponent);
  print_kv("pile_slope", c.height_slope);
  print_kv("repose_angle_deg", c.repose_angle_deg);
  char notes[400];
  std::snprintf(notes, sizeof notes,
                "{\"from\": \"soc\", \"model\": \"extended 2D heap, %lld columns, %lld grains at the centre, critical step %d\", "
                "\"large_avalanches\": %lld, \"pile_height_exponent\": %.4g, \"pile_slope\": %.4g}",
                static_cast<long long>(c.columns), static_cast<long long>(c.grains), o.critical_step,
                static_cast<long long>(c.large_avalanches), c.height_exponent, c.height_slope);
  sim::Scene scene = c.scene;
  scene.avalanche.enabled = scene.avalanche.enabled || c.large_avalanches > 1;
  scene.column.pile_grows = true;
  return write_scene(o, scene, notes);
}

int calibrate_fluid(const CalibrateOptions& o, const sim::Scene& base) {
  const FluidSceneCalibration c = calibrate_from_fluid(base, o.grid);
  std::printf("scene=%s\nfrom=fluid\ngrid=%d\nshape=circle\nbore_m=%.5g\nmultigrid_cycles=%d\n", base.name.c_str(), c.grid,
              base.silo.bore_m, c.iterations);
  print_kv("flow_factor", c.alpha);
  char notes[200];
  std::snprintf(notes, sizeof notes, "{\"from\": \"fluid\", \"model\": \"Poisson duct flow on the round bore, %d^2 grid, multigrid\"}",
                c.grid);
  return write_scene(o, c.scene, notes);
}

}  // namespace

int run_calibrate_command(int argc, char** argv) {
  CLI::App app{"Calibrate a lumped scene from a detail model: dem (Beverloo C/k, flow factor, start-up, impact "
               "relaxation), soc (avalanche F_a, critical mass, duration, pile height law), fluid (flow factor)"};
  CalibrateOptions o;
  app.add_option("--from", o.from, "detail model")->required()->check(CLI::IsMember({"dem", "soc", "fluid"}));
  app.add_option("--scene", o.scene, "scene to calibrate (name or .json)");
  app.add_option("--out", o.out, "write the calibrated scene file here");
  app.add_option("--name", o.name, "name of the calibrated scene (default: the --out file's stem)");
  app.add_option("--seed", o.seed, "first seed (dem: one dose per seed from here; soc: the heap's ties)");
  app.add_option("--csv", o.csv, "dem: write t_s, DEM (seed mean) and calibrated lumped force and released mass");
  app.add_option("--jobs", o.jobs, "dem: threads running the DEM jobs (one process; under mpirun each rank runs "
                                   "one job at a time)")->check(CLI::Range(1, 256));
  app.add_option("--journal", o.journal, "dem: append each DEM job's result to FILE as it finishes");
  app.add_flag("--resume", o.resume, "dem: take the journal's finished jobs, compute only the missing ones");
  app.add_flag("--quiet", o.quiet, "no progress bar");
  app.add_flag("--compare", o.compare, "dem: the lumped-vs-DEM table: run time against error");
  app.add_option("--seeds", o.seeds, "dem: doses (seeds)")->check(CLI::Range(1, 1000));
  app.add_option("--close", o.dem.close_s, "dem: close command time of the dose, s")->check(CLI::Range(0.2, 10.0));
  app.add_option("--discs-across", o.dem.discs_across_orifice, "dem: discs across the bore")->check(CLI::Range(3.0, 60.0));
  app.add_option("--particles", o.dem.fill_discs, "dem: discs in the silo")->check(CLI::Range(50, 10000000));
  app.add_option("--sweep", o.dem.sweep_orifices, "dem: orifice widths in disc diameters for Beverloo's k")->delimiter(',');
  app.add_flag("--no-sweep", o.no_sweep, "dem: no width sweep (keep the scene's k, fit C at the bore)");
  app.add_option("--grains", o.grains, "soc: grains added")->check(CLI::Range(100LL, 100000000LL));
  app.add_option("--large-size", o.large_size, "soc: topplings of a large avalanche (0: a quarter of the columns)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--critical-step", o.critical_step, "soc: the heap's critical step")->check(CLI::Range(1, 100));
  app.add_option("--grid", o.grid, "fluid: grid points across the bore (2^k + 1)")->check(CLI::Range(9, 4097));
  if (const auto exit_status = tools::parse_command_line(app, argc, argv, "dynweigh calibrate")) return *exit_status;
  if (o.resume && o.journal.empty()) {
    std::fprintf(stderr, "dynweigh calibrate: --resume needs --journal FILE\n");
    return 2;
  }
  try {
    const std::optional<sim::Scene> base = sim::scene_by_name(o.scene);
    if (!base) return fail("calibrate", "unknown scene '" + o.scene + "' (see dynweigh sim --list)");
    for (const std::string* path : {&o.out, &o.csv}) {
      if (!path->empty()) check_writable(*path);  // before minutes of DEM, not after
    }
    if (o.from == "dem") return calibrate_dem(o, *base);
    if (o.from == "soc") return calibrate_soc(o, *base);
    return calibrate_fluid(o, *base);
  } catch (const std::exception& e) {
    return fail("calibrate", e.what());
  }
}

}  // namespace dynweigh::tools
