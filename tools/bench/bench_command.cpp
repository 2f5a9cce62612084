// dynweigh bench: strategies x scenarios x targets x seeds, closed loop through the same
// Indicator::step the firmware runs, judged by the plant's true mass. Prints a markdown table,
// then one key=value line per series; CSV and a PNG of run time against error on request.
// The series are the jobs of a scenario grid (tools/grid): threads, or MPI ranks under mpirun,
// journalled for --resume; every fill's seed is its index in the series, whoever runs it.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "bench_commands.hpp"
#include "fill_series.hpp"
#include "grid_runner.hpp"
#include "output_file.hpp"
#include "plant_family_bench.hpp"
#include "plant_family_ceiling.hpp"
#include "progress_bar.hpp"
#include "series_row.hpp"
#include "step_benchmark.hpp"
#ifdef DYNWEIGH_HAS_SIM_BENCH
#include "sim_commands.hpp"
#include "command_line.hpp"
#endif

namespace dynweigh::tools {
namespace {

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream stream(text);
  for (std::string part; std::getline(stream, part, ',');) {
    if (!part.empty()) parts.push_back(part);
  }
  return parts;
}

sim::Scene required_scene(const std::string& name) {
  const auto scene = sim::scene_by_name(name);
  if (!scene) throw std::runtime_error("unknown scene '" + name + "'");
  return *scene;
}

// The shipped scenes that dose into a container from one silo, plus the two stress scenarios.
// A scene with ingredients (batching) is benched only when --scenes names it: the bench doses
// ingredient 0 alone, and the default figures stay those of the one-silo scenes.
std::vector<std::string> default_scenarios() {
  std::vector<std::string> names;
  for (const auto& name : sim::scene_names()) {
    if (name == "hourglass") continue;  // silo on the scale: nothing to dose
    if (const auto scene = sim::scene_by_name(name); scene && !scene->ingredients.empty()) continue;
    names.push_back(name);
  }
  names.push_back("geometry-off-15");
  names.push_back("material-change");
  return names;
}

Scenario make_scenario(const std::string& name) {
  Scenario scenario;
  scenario.name = name;
  if (name == "geometry-off-15") {
    scenario.scene = required_scene("default");
    scenario.geometry_error = 0.15;
  } else if (name == "material-change") {
    scenario.scene = required_scene("default");
    scenario.material_change = true;
  } else {
    scenario.scene = required_scene(name);
  }
  return scenario;
}

std::string class_text(double x) {
  if (x <= 0.0) return "none";
  std::ostringstream out;
  out << "X(" << x << ")";
  return out.str();
}

std::string format_line(const SeriesResult& r, const std::vector<Scenario>& scenarios) {
  char line[512];
  std::snprintf(line, sizeof line,
                "strategy=%s knob=%g scene=%s target_g=%.0f time_ratio=%.3f time_ratio_max=%.3f bias_g=%.1f "
                "sd_g=%.1f maxdev_g=%.1f class=%s failed=%zu claim_error_max_g=%.1f",
                bench_strategy_name(r.spec.strategy), r.spec.knob, scenarios[r.spec.scenario].name.c_str(),
                r.spec.target_g, r.time_ratio_mean, r.time_ratio_max, r.bias_g, r.sd_g, r.max_deviation_g,
                class_text(r.oiml_class).c_str(), r.failed, r.worst_reported_vs_true_g);
  return line;
}

void write_csv(const std::string& path, const std::vector<SeriesResult>& results,
               const std::vector<Scenario>& scenarios) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << "strategy,knob,scene,target_g,time_ratio,time_ratio_max,bias_g,sd_g,maxdev_g,class,failed\n";
  for (const auto& r : results) {
    out << bench_strategy_name(r.spec.strategy) << ',' << r.spec.knob << ',' << scenarios[r.spec.scenario].name << ','
        << r.spec.target_g << ',' << r.time_ratio_mean << ',' << r.time_ratio_max << ',' << r.bias_g << ','
        << r.sd_g << ',' << r.max_deviation_g << ',' << r.oiml_class << ',' << r.failed << '\n';
  }
}

void write_png(const std::string& path, const std::vector<SeriesResult>& results,
               const std::vector<Scenario>& scenarios) {
  // One panel: every series' mean time ratio against its maximum deviation, a colour per strategy.
  std::map<std::string, std::string> points;
  for (const auto& r : results) {
    if (r.fills == r.failed) continue;
    points[bench_strategy_name(r.spec.strategy)] += std::to_string(r.time_ratio_mean) + " " +
                                                    std::to_string(std::max(r.max_deviation_g, 0.1)) + " " +
                                                    scenarios[r.spec.scenario].name + "\n";
  }
  std::ostringstream gp;
  gp << "set terminal pngcairo size 1100,700 font 'Sans,11'\nset output '" << path << "'\n"
     << "set title 'dynweigh bench: run time against error (every series)'\n"
     << "set xlabel 'fill time / physical minimum'\nset ylabel 'max deviation of a fill from the mean (g)'\n"
     << "set logscale y\nset grid\nset key top right box\nplot ";
  bool first = true;
  for (const auto& entry : points) {
    gp << (first ? "" : ", ") << "'-' using 1:2 with points pt 7 ps 1.2 title '" << entry.first << "'";
    first = false;
  }
  gp << "\n";
  for (const auto& entry : points) gp << entry.second << "e\n";
  run_gnuplot(gp.str(), path);
}

// The files the run will write, checked (and created) before the grid runs for minutes or hours.
// Adds those the check created to `created`, for removal if the run fails.
void check_outputs(const std::string& csv, const std::string& png, const std::string& journal,
                   std::vector<std::string>& created) {
  if (!png.empty()) {
    require_extension(png, "png", "--png");
    require_gnuplot();
  }
  for (const std::string* path : {&csv, &png}) {
    if (!path->empty() && check_writable(*path)) created.push_back(*path);
  }
  // The journal is rewritten through JOURNAL.tmp: its folder must take a new file.
  if (!journal.empty() && check_writable(journal + ".tmp")) std::remove((journal + ".tmp").c_str());
}

double parse_target(const std::string& text, const Scenario& scenario) {
  double target = 0.0;
  try {
    target = std::stod(text);
  } catch (const std::logic_error&) {
    throw std::runtime_error("target '" + text + "' is not a number");
  }
  if (!(target >= 1.0 && target <= scenario.scene.load_cell.capacity_kg * 1000.0)) {
    throw std::runtime_error("target " + text + " g is outside the scale's range");
  }
  return target;
}

// The grid in its canonical order: strategy, knob, scenario, target.
std::vector<SeriesSpec> series_specs(const std::string& strategies, const std::string& targets, bool sweep,
                                     const std::vector<Scenario>& scenarios) {
  std::vector<SeriesSpec> specs;
  for (const auto& name : split(strategies)) {
    BenchStrategy strategy;
    if (!parse_bench_strategy(name, strategy)) throw std::runtime_error("unknown strategy '" + name + "'");
    const bool two_stage = strategy == BenchStrategy::twostage || strategy == BenchStrategy::twostage_dyn;
    std::vector<double> knobs{0.0};
    if (two_stage) knobs = sweep ? std::vector<double>{0.25, 0.5, 1.0, 1.5, 2.5} : std::vector<double>{1.0};
    if ((strategy == BenchStrategy::model || strategy == BenchStrategy::learn) && sweep) {
      knobs = {0.0, 0.25, 0.5, 1.0, 1.5, 2.5};
    }
    for (double knob : knobs) {
      for (std::size_t s = 0; s < scenarios.size(); ++s) {
        for (const auto& t : split(targets)) specs.push_back({strategy, knob, s, parse_target(t, scenarios[s])});
      }
    }
  }
  return specs;
}

// --plants: the family, its strategies (no oracles by default) and its targets (every one the issue
// names by default), and none of the scene grid's options.
int run_plants(const CLI::App& app, const std::string& plants, const std::string& strategies, const std::string& targets,
               std::uint32_t fills, unsigned jobs, bool quiet, const grid::ParallelSession& session) {
  for (const char* option : {"--scenes", "--seeds", "--sweep", "--csv", "--png", "--journal", "--resume"}) {
    if (app.count(option)) throw std::runtime_error(std::string(option) + " is not for --plants");
  }
  const bool ceiling = app.count("--ceiling") > 0;
  if (ceiling && app.count("--strategies")) throw std::runtime_error("--strategies is not for --ceiling (no strategy runs)");
  PlantFamilyOptions options;
  options.plants = parse_plant_family_spec(plants);
  options.strategies = split(app.count("--strategies") ? strategies : "model,learn,preact,twostage");
  if (app.count("--targets")) {
    Scenario scale;  // the family's scale: Max 50 kg
    for (const auto& t : split(targets)) options.targets_g.push_back(parse_target(t, scale));
  } else {
    options.targets_g = kPlantFamilyTargetsG;
  }
  options.fills = fills;
  options.threads = jobs;
  options.progress = !quiet;
  if (ceiling) run_plant_family_ceiling(options, session);
  else run_plant_family_bench(options, session);
  return 0;
}

}  // namespace

int run_bench_command(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--step") return run_step_benchmark(argc - 1, argv + 1);
#ifdef DYNWEIGH_HAS_SIM_BENCH
    if (std::string(argv[i]) == "--sim") return run_sim_bench(argc, argv);
#endif
  }
  std::string strategies = "model,learn,preact,twostage,twostage-dyn,pac,flowpreact,oracle,oracle-scale";
  std::string scene_list, targets = "500,2000,5000,10000,15000", csv, png, journal;
  std::uint32_t seeds = 50, fills = 6;
  std::string plants;
  unsigned jobs = std::max(1u, std::thread::hardware_concurrency());
  bool sweep = false, quiet = false, resume = false;
  CLI::App app{"dynweigh bench: strategies x scenes x targets x seeds, closed loop through Indicator::step, judged\n"
               "by the plant's true mass. `--step`: Google Benchmark of Indicator::step. `--sim`: the plant's\n"
               "speed and accuracy per scene."};
  app.add_option("--strategies", strategies,
                 "model,learn,preact,twostage,twostage-dyn,pac,flowpreact,oracle,oracle-scale (oracle: reads the "
                 "plant's present truth; oracle-scale: only what has landed, as a perfect scale)")
      ->capture_default_str();
  app.add_option("--scenes", scene_list, "scenes and scenarios (default: every dosing scene, geometry-off-15, "
                                          "material-change)");
  app.add_option("--targets", targets, "targets in grams")->capture_default_str();
  app.add_option("--seeds", seeds, "fills per series")->capture_default_str()->check(CLI::Range(2u, 100000u));
  app.add_option("--jobs", jobs, "worker threads (one process; under mpirun each rank runs one series at a time)")
      ->check(CLI::Range(1u, 256u));
  app.add_flag("--sweep", sweep, "sweep each strategy's speed knob: the half-open fine feed, in seconds of full "
                               "flow (model: model_fine_s, twostage: its band)");
  app.add_option("--csv", csv, "write the series as CSV");
  app.add_option("--png", png, "draw run time against error");
  app.add_option("--journal", journal, "append each series' result to FILE as it finishes (default: the --csv "
                                       "file + .journal; none without --csv)");
  app.add_flag("--resume", resume, "take the journal's finished series, compute only the missing ones");
  app.add_option("--plants", plants, "random:N[@SEED] (SEED 1 unless given): N plants drawn across the physical "
                                     "ranges, each commissioned through the console, each target dosed --fills times "
                                     "(targets 500,1000,2000,5000,10000,15000 g unless --targets; those the plant holds)");
  app.add_option("--fills", fills, "--plants: fills per target, back to back")->capture_default_str()
      ->check(CLI::Range(2u, 1000u));
  app.add_flag("--ceiling", "--plants: instead of the strategies, the chance that a controller knowing each plant "
                            "exactly lands a fill within X(1) with at most 3 pulses (docs/plant-family.md)");
  app.add_flag("--quiet", quiet, "no progress bar");
  app.add_flag("--step", "Google Benchmark of Indicator::step (other options go to Google Benchmark)");
  app.add_flag("--sim", "the plant's realtime factor and error per scene");
  if (const auto exit_status = tools::parse_command_line(app, argc, argv, "dynweigh bench")) return *exit_status;
  if (journal.empty() && !csv.empty()) journal = csv + ".journal";
  if (resume && journal.empty()) {
    std::fprintf(stderr, "dynweigh bench: --resume needs --journal FILE or --csv FILE\n");
    return 2;
  }
  const grid::ParallelSession session(true);
  std::vector<std::string> created;
  try {
    if (app.count("--plants")) return run_plants(app, plants, strategies, targets, fills, jobs, quiet, session);
    if (app.count("--fills")) throw std::runtime_error("--fills is for --plants (a scene's series: --seeds)");
    if (app.count("--ceiling")) throw std::runtime_error("--ceiling is for --plants");
    if (session.writer()) check_outputs(csv, png, journal, created);
    std::vector<Scenario> scenarios;
    for (const auto& name : scene_list.empty() ? default_scenarios() : split(scene_list)) {
      scenarios.push_back(make_scenario(name));
    }
    const std::vector<SeriesSpec> specs = series_specs(strategies, targets, sweep, scenarios);
    std::vector<std::string> keys;
    for (const auto& spec : specs) keys.push_back(series_key(spec, scenarios));

    ProgressBar bar("bench", specs.size(), !quiet && session.writer());
    grid::GridOptions options;
    options.threads = jobs;
    options.journal_path = journal;
    options.resume = resume;
    options.signature = "bench seeds=" + std::to_string(seeds);
    options.progress = [&bar](std::size_t finished, std::size_t) { bar.update(finished); };
    const grid::GridOutcome outcome = grid::run_grid(
        session, keys,
        [&](std::size_t i) { return encode_series_row(run_series(specs[i], scenarios[specs[i].scenario], seeds)); },
        options);
    bar.finish();
    if (!session.writer()) return 0;
    std::vector<SeriesResult> results;
    for (std::size_t i = 0; i < specs.size(); ++i) results.push_back(decode_series_row(specs[i], outcome.rows[i]));
    if (!journal.empty() || session.distributed()) grid::report_grid(outcome, session, journal);

    std::printf("| strategy | knob | scene | target g | time / t_phys (mean, max) | bias g | sd g | max dev g | class |\n");
    std::printf("| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
    for (const auto& r : results) {
      std::printf("| %s | %g | %s | %.0f | %.3f, %.3f | %.1f | %.1f | %.1f | %s%s |\n", bench_strategy_name(r.spec.strategy),
                  r.spec.knob, scenarios[r.spec.scenario].name.c_str(), r.spec.target_g, r.time_ratio_mean,
                  r.time_ratio_max, r.bias_g, r.sd_g, r.max_deviation_g, class_text(r.oiml_class).c_str(),
                  r.failed ? (" (" + std::to_string(r.failed) + " failed)").c_str() : "");
    }
    std::printf("\n");
    for (const auto& r : results) std::printf("%s\n", format_line(r, scenarios).c_str());
    if (!csv.empty()) write_csv(csv, results, scenarios);
    if (!png.empty()) write_png(png, results, scenarios);
    return 0;
  } catch (const std::exception& e) {
    for (const std::string& path : created) std::remove(path.c_str());  // no empty output left behind
    std::fprintf(stderr, "dynweigh bench: %s\n", e.what());
    if (session.distributed()) session.abort(1);  // the other ranks would wait for jobs forever
    return 1;
  }
}

}  // namespace dynweigh::tools
