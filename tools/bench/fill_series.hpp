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
