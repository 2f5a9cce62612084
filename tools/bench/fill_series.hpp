#pragma once
// A series of fills of one strategy, scenario and target over seeds, each judged by the plant's
// true mass. The indicator's settings carry from fill to fill, so learning strategies learn.
#include <cstdint>
#include <string>
#include <vector>

#include "dynweigh/firmware/persistent_settings.hpp"
#include "dynweigh/sim/scene.hpp"

namespace dynweigh::tools {

// A plant and what the indicator is told about it.
struct Scenario {
  std::string name;
  sim::Scene scene;
  double geometry_error = 0.0;    // the installation values the firmware gets are off by this fraction
  bool material_change = false;   // halfway through a series the plant's material changes
};

// oracle and oracle_scale are simulation-only limits that read the plant's truth (fill_series.cpp).
enum class BenchStrategy { model, preact, twostage, twostage_dyn, oracle, learn, oracle_scale, pac, flowpreact };
const char* bench_strategy_name(BenchStrategy strategy);
bool parse_bench_strategy(const std::string& name, BenchStrategy& strategy);

struct SeriesSpec {
  BenchStrategy strategy = BenchStrategy::model;
  double knob = 0.0;  // the half-open fine feed in seconds of full flow (model, twostage)
  std::size_t scenario = 0;
  double target_g = 0.0;
};

struct SeriesResult {
  SeriesSpec spec;
  std::size_t fills = 0;
  std::size_t failed = 0;          // faults or missing results
  double time_ratio_mean = 0.0;    // fill time / t_phys
  double time_ratio_max = 0.0;
  double bias_g = 0.0;             // mean of true fill - target
  double sd_g = 0.0;
  double max_deviation_g = 0.0;    // largest |fill - mean of fills|
  double worst_reported_vs_true_g = 0.0;
  double oiml_class = 0.0;         // 0: none
};

// One fill as an operator doses it: `dose <target> <strategy>` typed on the console of an
// indicator with `settings`, on a fresh plant of `scene` (the container empty, the silo full) run
// with `seed`. Judged by the plant's true mass; what the indicator learned goes back to `settings`.
struct ConsoleFill {
  bool ok = false;
  double true_fill_g = 0.0;
  double reported_fill_g = 0.0;
  double time_s = 0.0;
  long topups = 0;     // RESULT's topups=, 0 where it has none
  std::string error;   // the indicator's ERR line, when it refused or failed
};
ConsoleFill dose_through_console(const sim::Scene& scene, std::uint64_t seed, const std::string& strategy,
                                 double target_g, firmware::PersistentSettings& settings);

// The word `dose` takes for a bench strategy.
const char* firmware_strategy(BenchStrategy strategy);

// A strategy's set-up on an installed indicator, as a series of the bench gets it: its knob, its
// certification, and for preact and twostage the engineer's preact from trial fills (never counted).
void set_up_strategy(const SeriesSpec& spec, const Scenario& scenario, firmware::PersistentSettings& settings);

// The physical minimum time of a fill: valve dead time + target / full flow + fall time.
double physical_minimum_s(const sim::Scene& scene, double target_g);

// The scene a fill of a series runs: the scenario's, with the material changed for the second
// half of a material-change series.
sim::Scene scene_for_fill(const Scenario& scenario, std::size_t fill_index, std::size_t fills);

SeriesResult run_series(const SeriesSpec& spec, const Scenario& scenario, std::uint32_t seeds);

// An adaptive baseline as an integrator first meets it: the installation values and the knob, every
// other parameter at its default, no trial fills; then `fills` fills (seeds 1..fills) learning from
// each other. Each fill's error by the plant's true mass (NaN for a fill that failed).
std::vector<double> fills_from_defaults(const SeriesSpec& spec, const Scenario& scenario, std::uint32_t fills);

}  // namespace dynweigh::tools
