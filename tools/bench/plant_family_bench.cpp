// The plant family bench. A job of the grid is one strategy on one plant: the plant commissioned
// through the console from a blank indicator, then its targets in ascending order, each `fills`
// times back to back, what the indicator learned carried from fill to fill and target to target.
// Every fill runs on a fresh plant (an empty container, a full silo: the simulator has no discharge
// gate) with the indicator restarted from its persistent settings, so what carries over is what a
// power-safe indicator keeps. Seeds depend on the plant, target and fill, never on the strategy:
// every strategy meets the same plants, flows and noise.
#include "plant_family_bench.hpp"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "dynweigh/firmware/tolerance.hpp"
#include "dynweigh/hal/host/lockstep_session.hpp"
#include "dynweigh/hal/host/scripted_console.hpp"
#include "dynweigh/sim/plant_family.hpp"
#include "family_comparison.hpp"
#include "fill_series.hpp"
#include "grid_runner.hpp"
#include "dynweigh/model/oiml_r61_class.hpp"
#include "progress_bar.hpp"

namespace dynweigh::tools {
namespace {

constexpr std::uint32_t kMostPlants = 10000;
constexpr double kTestWeightG = 20000.0;      // 40 % of Max, in whole divisions
constexpr double kSetDownWaitS = 5.0;          // the integrator waits for the display to settle
constexpr int kAdjustmentTries = 12;           // `ERR 3 in motion` (10 s each): type it again
constexpr double kAnswerLimitS = 60.0;
constexpr char kCellSeparator = ';';

// A console typed into one line at a time, each run until its final answer.
class ConsoleDriver {
 public:
  explicit ConsoleDriver(hal::host::LockstepSession& session)
      : session_(session),
        console_(
            [this](std::string& line) {
              if (pending_.empty()) return hal::host::ScriptedConsole::Poll::nothing_yet;
              line.swap(pending_);
              pending_.clear();
              return hal::host::ScriptedConsole::Poll::line;
            },
            [this](const char* data, std::size_t n) { output_.append(data, n); }) {}

  void idle(double seconds) {
    for (double t = 0.0; t < seconds; t += hal::host::LockstepSession::kJiffyS) step();
  }

  // The answer: every line up to and including OK or ERR ("" if none came within the limit).
  std::string command(const std::string& line) {
    output_.clear();
    pending_ = line;
    for (double t = 0.0; t < kAnswerLimitS; t += hal::host::LockstepSession::kJiffyS) {
      step();
      if (answered()) return output_;
    }
    return "";
  }

 private:
  void step() { console_.set_indicator_busy(session_.step(console_).busy); }

  bool answered() const {
    if (output_.empty() || output_.back() != '\n') return false;
    const auto start = output_.rfind('\n', output_.size() - 2);
    const std::string last = output_.substr(start == std::string::npos ? 0 : start + 1);
    return last == "OK\n" || last.rfind("ERR", 0) == 0;
  }

  hal::host::LockstepSession& session_;
  hal::host::ScriptedConsole console_;
  std::string pending_;
  std::string output_;
};

bool ends_ok(const std::string& answer) {
  return answer.size() >= 3 && answer.compare(answer.size() - 3, 3, "OK\n") == 0;
}

std::string one_line(std::string text) {
  while (!text.empty() && text.back() == '\n') text.pop_back();
  for (char& c : text) c = c == '\n' ? '/' : c;
  return text.empty() ? "no answer" : text;
}

std::uint64_t mix(std::uint64_t a, std::uint64_t b) {
  std::uint64_t z = a * 0x9E3779B97F4A7C15ULL + b + 0x632BE59BD9B4E019ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

std::uint64_t commissioning_seed(std::uint64_t family_seed, std::uint32_t plant) {
  return mix(mix(family_seed, plant), 0xC0FFEE);
}

std::uint64_t fill_seed(std::uint64_t family_seed, std::uint32_t plant, std::size_t target, std::uint32_t fill) {
  return mix(mix(mix(family_seed, plant), target + 1), fill + 1);
}

void expect_ok(const std::string& plant, const std::string& line, const std::string& answer) {
  if (!ends_ok(answer)) throw std::runtime_error(plant + ": `" + line + "` answered " + one_line(answer));
}

// An adjustment (`zero`, `cal`) waits for standstill; on a lively platform it may time out and is typed again.
std::string adjust(ConsoleDriver& console, const std::string& plant, const std::string& line) {
  std::string answer;
  for (int i = 0; i < kAdjustmentTries; ++i) {
    answer = console.command(line);
    if (ends_ok(answer)) return answer;
    if (answer.find("ERR 3") == std::string::npos) break;
  }
  expect_ok(plant, line, answer);
  return answer;
}

std::string param_line(const char* name, double value) {
  char line[80];
  std::snprintf(line, sizeof line, "param %s %.1f", name, value);
  return line;
}

// A blank indicator (no calibration, every parameter at its default) commissioned as an integrator
// does: `zero` on the empty hopper, a test weight and `cal`, the installation's geometry true and
// the density a guess; valve timing, platform and everything else left at the defaults.
firmware::PersistentSettings commission(const sim::FamilyPlant& plant, std::uint64_t seed) {
  const std::string& name = plant.scene.name;
  hal::host::LockstepSession session(plant.scene, seed, firmware::PersistentSettings{});
  ConsoleDriver console(session);
  console.idle(1.0);
  adjust(console, name, "zero");
  session.plant().place_test_weight(kTestWeightG / 1000.0);
  console.idle(kSetDownWaitS);
  adjust(console, name, "cal " + std::to_string(std::lround(kTestWeightG)));
  session.plant().place_test_weight(0.0);
  const sim::Scene& s = plant.scene;
  for (const std::string& line : {param_line("bore_mm", s.silo.bore_m * 1000.0),
                                  param_line("fall_mm", s.column.fall_height_m * 1000.0),
                                  param_line("container_mm", s.column.container_diameter_m * 1000.0),
                                  param_line("density", plant.density_guess)}) {
    expect_ok(name, line, console.command(line));
  }
  return session.indicator().settings();
}

std::string class_text(double x) {
  if (x <= 0.0) return "none";
  std::ostringstream out;
  out << "X(" << x << ")";
  return out.str();
}

double class_value(const std::string& line, const char* key) {
  const std::string field = std::string(key) + "=X(";
  const auto at = line.find(field);
  return at == std::string::npos ? 0.0 : std::strtod(line.c_str() + at + field.size(), nullptr);
}

struct Cell {
  double first_error_g = NAN;
  std::vector<double> steady_errors_g;
  std::size_t failed = 0;
  double time_ratio_sum = 0.0;
  std::size_t timed = 0;
  long topups = 0;
  std::string failure = "-";  // the first failed fill's answer, one word
};

// "ERR 4 fault no_flow" -> "fault_no_flow"; a fill that ended without an answer: "no_result".
std::string failure_word(const std::string& error) {
  if (error.empty()) return "no_result";
  std::string word = error.rfind("ERR ", 0) == 0 && error.size() > 6 ? error.substr(6) : error;
  for (char& c : word) c = c == ' ' || c == '=' ? '_' : c;
  return word;
}

std::string cell_line(const std::string& strategy, const std::string& plant, double target_g, const Cell& c,
                      std::uint32_t fills) {
  const bool first_ok = !std::isnan(c.first_error_g);
  const double class_first = first_ok ? model::oiml_class_of_deviation(target_g, std::abs(c.first_error_g)) : 0.0;
  double bias = 0.0, max_deviation = 0.0;
  for (double e : c.steady_errors_g) bias += e / double(c.steady_errors_g.size());
  for (double e : c.steady_errors_g) max_deviation = std::max(max_deviation, std::abs(e - bias));
  const bool steady_ok = c.steady_errors_g.size() + 1 == fills;
  const double class_steady = steady_ok ? model::best_oiml_class(target_g, max_deviation, bias) : 0.0;
  char line[400];
  std::snprintf(line, sizeof line,
                "strategy=%s plant=%s target_g=%.0f class_first=%s class_steady=%s time_ratio=%.3f topups=%ld "
                "first_error_g=%.1f steady_bias_g=%.1f steady_maxdev_g=%.1f failed=%zu failure=%s",
                strategy.c_str(), plant.c_str(), target_g, class_text(class_first).c_str(),
                class_text(class_steady).c_str(), c.timed ? c.time_ratio_sum / double(c.timed) : 0.0, c.topups,
                first_ok ? c.first_error_g : 0.0, bias, max_deviation, c.failed, c.failure.c_str());
  return line;
}

bool refuses_strategy(const std::string& error) {
  return error.find("unknown strategy") != std::string::npos || error.find("not in this build") != std::string::npos;
}

// One strategy on one plant: its cells' lines, joined by kCellSeparator ("-" when it holds no target).
std::string plant_job(const PlantFamilyOptions& o, const std::string& strategy, std::uint32_t index) {
  const sim::FamilyPlant plant = sim::draw_family_plant(o.plants.seed, index);
  firmware::PersistentSettings settings = commission(plant, commissioning_seed(o.plants.seed, index));
  const Scenario scenario{plant.scene.name, plant.scene};
  BenchStrategy bench_strategy = BenchStrategy::model;
  const bool known = parse_bench_strategy(strategy, bench_strategy);
  const std::string word = known ? firmware_strategy(bench_strategy) : strategy;
  std::string row;
  for (std::size_t t = 0; t < o.targets_g.size(); ++t) {
    const double target_g = o.targets_g[t];
    if (!sim::family_plant_holds(plant.scene, target_g / 1000.0)) continue;
    if (known) {
      const bool two_stage = bench_strategy == BenchStrategy::twostage || bench_strategy == BenchStrategy::twostage_dyn;
      set_up_strategy({bench_strategy, two_stage ? 1.0 : 0.0, 0, target_g}, scenario, settings);
      // Every baseline gets the top-up industrial indicators offer (its fixed `topup_ms` pulses);
      // the model tops up by itself.
      if (bench_strategy != BenchStrategy::model && bench_strategy != BenchStrategy::learn) {
        settings.parameters.set(firmware::ParameterId::tol_action, float(firmware::ToleranceAction::topup));
      }
    }
    const double t_phys = physical_minimum_s(plant.scene, target_g);
    Cell cell;
    for (std::uint32_t k = 0; k < o.fills; ++k) {
      const ConsoleFill f =
          dose_through_console(plant.scene, fill_seed(o.plants.seed, index, t, k), word, target_g, settings);
      if (!f.ok) {
        if (refuses_strategy(f.error)) throw std::runtime_error("strategy '" + strategy + "': " + f.error);
        ++cell.failed;
        if (cell.failure == "-") cell.failure = failure_word(f.error);
        continue;
      }
      const double error_g = f.true_fill_g - target_g;
      if (k == 0) cell.first_error_g = error_g;
      else cell.steady_errors_g.push_back(error_g);
      cell.time_ratio_sum += f.time_s / t_phys;
      ++cell.timed;
      cell.topups += f.topups;
    }
    if (!row.empty()) row += kCellSeparator;
    row += cell_line(strategy, plant.scene.name, target_g, cell, o.fills);
  }
  return row.empty() ? "-" : row;
}

// A strategy the simulation's oracles are (they read the plant's truth) or the firmware does not know.
void check_strategies(const std::vector<std::string>& strategies) {
  if (strategies.empty()) throw std::runtime_error("--strategies names none");
  const sim::FamilyPlant plant = sim::draw_family_plant(1, 0);
  for (const std::string& name : strategies) {
    BenchStrategy strategy;
    if (parse_bench_strategy(name, strategy) &&
        (strategy == BenchStrategy::oracle || strategy == BenchStrategy::oracle_scale)) {
      throw std::runtime_error("strategy '" + name + "' reads the plant's truth: not with --plants");
    }
    const std::string word = parse_bench_strategy(name, strategy) ? firmware_strategy(strategy) : name;
    // A blank indicator checks the strategy before it checks its calibration.
    hal::host::LockstepSession session(plant.scene, 1, firmware::PersistentSettings{});
    ConsoleDriver console(session);
    const std::string answer = console.command("dose 500 " + word);
    if (refuses_strategy(answer)) throw std::runtime_error("unknown strategy '" + name + "'");
  }
}

}  // namespace

PlantFamilySpec parse_plant_family_spec(const std::string& text) {
  const std::string why = "--plants '" + text + "': expected random:N or random:N@SEED (N 1-" +
                          std::to_string(kMostPlants) + ", SEED a whole number)";
  const std::string kind = "random:";
  if (text.compare(0, kind.size(), kind) != 0) throw std::runtime_error(why);
  const std::string rest = text.substr(kind.size());
  const auto at = rest.find('@');
  const std::string count = rest.substr(0, at);
  const std::string seed = at == std::string::npos ? "1" : rest.substr(at + 1);
  const auto whole = [](const std::string& digits) {
    return !digits.empty() && digits.size() <= 19 && digits.find_first_not_of("0123456789") == std::string::npos;
  };
  if (!whole(count) || !whole(seed)) throw std::runtime_error(why);
  PlantFamilySpec spec;
  const unsigned long long n = std::stoull(count);
  if (n < 1 || n > kMostPlants) throw std::runtime_error(why);
  spec.count = std::uint32_t(n);
  spec.seed = std::stoull(seed);
  return spec;
}

void run_plant_family_bench(const PlantFamilyOptions& o, const grid::ParallelSession& session) {
  if (o.fills < 2) throw std::runtime_error("--fills must be 2 or more (a first fill and a steady one)");
  check_strategies(o.strategies);
  std::vector<std::string> keys;
  for (const std::string& strategy : o.strategies) {
    for (std::uint32_t p = 0; p < o.plants.count; ++p) {
      keys.push_back("strategy=" + strategy + " plant=random-" + std::to_string(p + 1));
    }
  }
  ProgressBar bar("bench --plants", keys.size(), o.progress && session.writer());
  grid::GridOptions options;
  options.threads = o.threads;
  options.signature = "bench plants";
  options.progress = [&bar](std::size_t finished, std::size_t) { bar.update(finished); };
  const grid::GridOutcome outcome = grid::run_grid(
      session, keys,
      [&](std::size_t job) {
        return plant_job(o, o.strategies[job / o.plants.count], std::uint32_t(job % o.plants.count));
      },
      options);
  bar.finish();
  if (!session.writer()) return;
  std::vector<std::string> summaries, cell_lines;
  for (std::size_t s = 0; s < o.strategies.size(); ++s) {
    std::size_t cells = 0, first_x1 = 0, steady_x1 = 0;
    for (std::uint32_t p = 0; p < o.plants.count; ++p) {
      std::istringstream row(outcome.rows[s * o.plants.count + p]);
      for (std::string line; std::getline(row, line, kCellSeparator);) {
        if (line == "-") continue;
        std::printf("%s\n", line.c_str());
        cell_lines.push_back(line);
        const double first = class_value(line, "class_first"), steady = class_value(line, "class_steady");
        ++cells;
        first_x1 += first > 0.0 && first <= 1.0;
        steady_x1 += steady > 0.0 && steady <= 1.0;
      }
    }
    const double n = cells ? double(cells) : 1.0;
    char summary[300];
    std::snprintf(summary, sizeof summary,
                  "summary strategy=%s plants=%" PRIu32 " seed=%" PRIu64 " fills=%" PRIu32
                  " cells=%zu first_x1_share=%.3f steady_x1_share=%.3f",
                  o.strategies[s].c_str(), o.plants.count, o.plants.seed, o.fills, cells, double(first_x1) / n,
                  double(steady_x1) / n);
    summaries.push_back(summary);
  }
  if (const auto comparison = family_comparison_summary(cell_lines)) summaries.push_back(*comparison);
  for (const std::string& summary : summaries) std::printf("%s\n", summary.c_str());
}

}  // namespace dynweigh::tools
