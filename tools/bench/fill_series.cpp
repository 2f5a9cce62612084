#include "fill_series.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <iterator>

#include "dynweigh/hal/host/lockstep_session.hpp"
#include "dynweigh/hal/host/scripted_console.hpp"
#include "dynweigh/model/bore_area.hpp"
#include "dynweigh/model/ideal_model.hpp"
#include "dynweigh/model/valve_let_through.hpp"
#include "dynweigh/sim/plant.hpp"
#include "dynweigh/model/oiml_r61_class.hpp"

namespace dynweigh::tools {
namespace {

constexpr double kJiffyS = hal::host::LockstepSession::kJiffyS;
constexpr std::uint32_t kMaxJiffies = 20000;          // 200 s: any fill of the shipped scenes is shorter
constexpr std::uint64_t kTrialSeedBase = 900000;      // the engineer's trial fills, never measured
constexpr std::uint32_t kTrialFills = 5;
constexpr std::uint32_t kWarmUpFills = 5;             // adaptive strategies learn before we measure

const char* const kNames[] = {"model",        "preact", "twostage",  "twostage-dyn", "oracle",
                              "learn",        "oracle-scale", "pac", "flowpreact"};
static_assert(std::size(kNames) == static_cast<std::size_t>(BenchStrategy::flowpreact) + 1,
              "one name per BenchStrategy, in its order");

// oracle-scale's landing rate: the mean over the last second (or since the stream landed), like
// the model's. The material in flight left the orifice after what is landing now, and the silo's
// flow forgets its wandering (0.15 s) within a third of the fall, so the mean foretells it best: on
// the default scene at 10 kg (50 seeds) the last 0.1 s gives 94 g max deviation, the last 1 s 49 g.
constexpr std::uint32_t kLandingWindowJiffies = 100;

using Fill = ConsoleFill;

// What the installer types in: the plant's geometry (off by the scenario's error) and its valve's
// datasheet timing. Nothing else is tuned.
firmware::PersistentSettings installation(const Scenario& scenario, const sim::Plant& plant) {
  firmware::PersistentSettings settings = hal::host::factory_settings(plant);
  firmware::Parameters& p = settings.parameters;
  const sim::Scene& s = scenario.scene;
  const double off = 1.0 + scenario.geometry_error;
  using firmware::ParameterId;
  p.set(ParameterId::bore_mm, float(s.silo.bore_m * 1000.0 * off));
  p.set(ParameterId::fall_mm, float(s.column.fall_height_m * 1000.0 * off));
  p.set(ParameterId::container_mm, float(s.column.container_diameter_m * 1000.0 * off));
  p.set(ParameterId::density, float(s.silo.bulk_density * off));
  p.set(ParameterId::capacity_g, float(s.load_cell.capacity_kg * 1000.0));
  p.set(ParameterId::valve_dead_ms, float(s.valve.dead_time_s * 1000.0));
  p.set(ParameterId::valve_stroke_ms, float(s.valve.full_stroke_s * 1000.0));
  p.set(ParameterId::repose_deg, float(s.column.repose_angle_deg));
  if (!s.column.pile_grows) p.set(ParameterId::pile_rise, 0.0f);
  return settings;
}

bool is_two_stage(BenchStrategy strategy) {
  return strategy == BenchStrategy::twostage || strategy == BenchStrategy::twostage_dyn;
}

const char* firmware_strategy_word(BenchStrategy strategy) {
  switch (strategy) {
    case BenchStrategy::preact: return "preact";
    case BenchStrategy::twostage:
    case BenchStrategy::twostage_dyn: return "twostage";
    case BenchStrategy::learn: return "learn";
    case BenchStrategy::pac: return "pac";
    case BenchStrategy::flowpreact: return "flowpreact";
    default: return "model";
  }
}

long field_value(const std::string& line, const char* key) {
  const auto at = line.find(std::string(key) + "=");
  return at == std::string::npos ? 0 : std::stol(line.substr(at + std::strlen(key) + 1));
}

}  // namespace

ConsoleFill dose_through_console(const sim::Scene& scene, std::uint64_t seed, const std::string& strategy,
                                 double target_g, firmware::PersistentSettings& settings) {
  hal::host::LockstepSession session(scene, seed, settings);
  std::string output;
  bool sent = false;
  const std::string command = "dose " + std::to_string(std::lround(target_g)) + " " + strategy;
  hal::host::ScriptedConsole console(
      [&](std::string& line) {
        if (sent) return false;
        line = command;
        sent = true;
        return true;
      },
      [&](const char* data, std::size_t n) { output.append(data, n); });
  console.set_indicator_busy(true);
  // The hopper stands empty a second before the fill: the display filter settles and the scale is
  // at rest, which the dose waits for.
  for (int i = 0; i < 100; ++i) session.step(console);
  console.set_indicator_busy(false);
  const double before_kg = session.plant().truth().static_kg;
  Fill fill;
  for (std::uint32_t j = 0; j < kMaxJiffies; ++j) {
    const firmware::Outputs out = session.step(console);
    console.set_indicator_busy(out.busy);
    if (sent && output.find("OK\n") != std::string::npos) break;
    const auto err = output.find("ERR");
    if (err != std::string::npos) {
      fill.error = output.substr(err, output.find('\n', err) - err);
      return fill;
    }
  }
  const auto at = output.find("RESULT ");
  if (at == std::string::npos) return fill;
  const std::string result = output.substr(at, output.find('\n', at) - at);
  fill.ok = true;
  fill.true_fill_g = (session.plant().truth().static_kg - before_kg) * 1000.0;
  fill.reported_fill_g = double(field_value(result, "final"));
  fill.time_s = double(field_value(result, "time")) / 1000.0;
  fill.topups = field_value(result, "topups");
  settings = session.indicator().settings();  // what it learned goes on to the next fill
  return fill;
}

const char* firmware_strategy(BenchStrategy strategy) { return firmware_strategy_word(strategy); }

namespace {

Fill indicator_fill(const sim::Scene& scene, std::uint64_t seed, BenchStrategy strategy, double target_g,
                    firmware::PersistentSettings& settings) {
  return dose_through_console(scene, seed, firmware_strategy(strategy), target_g, settings);
}

// The limit strategies' result: when the last grain has landed and the valve is shut, the plant's
// static mass is the fill, known exactly.
bool landed_and_shut(const sim::PlantTruth& t) { return t.in_flight_kg <= 0.0 && t.stroke <= 0.0; }

Fill limit_result(const sim::PlantTruth& t) {
  Fill fill;
  fill.ok = true;
  fill.true_fill_g = t.static_kg * 1000.0;
  fill.reported_fill_g = fill.true_fill_g;
  fill.time_s = t.time_s;
  return fill;
}

// The limits' valve let-through after a close, in seconds of full flow: from the plant's own valve
// timing and material, which only a simulation knows.
double true_let_through_s(const sim::Scene& scene) {
  const model::BeverlooMaterial<double> material{scene.silo.beverloo_C, scene.silo.beverloo_k, scene.silo.grain_d_m,
                                                 scene.silo.bulk_density};
  return model::closing_flow_seconds(material, scene.g, scene.silo.bore_m, scene.valve.dead_time_s,
                                     scene.valve.full_stroke_s);
}

// Closes within the coming jiffy if the fill now plus a jiffy of flow reaches the target, at the
// fraction of the jiffy where it does; true once closed.
bool close_within_jiffy(sim::Plant& plant, double now_kg, double flow_kg_s, double target_kg) {
  if (now_kg + flow_kg_s * kJiffyS < target_kg) return false;
  const double fraction = flow_kg_s > 0.0 ? std::clamp((target_kg - now_kg) / (flow_kg_s * kJiffyS), 0.0, 0.99) : 0.0;
  plant.command_valve(sim::ValveCommand::closed, fraction * kJiffyS);
  return true;
}

// The limit: a strategy that reads the plant's present truth each jiffy (static mass, mass in
// flight, present flow, the valve's let-through) but not its future disturbances, and closes
// within the jiffy when that truth reaches the target. It knows its result when the last grain lands.
Fill oracle_fill(const sim::Scene& scene, std::uint64_t seed, double target_g) {
  sim::Plant plant(scene, seed);
  const double let_through_s = true_let_through_s(scene);
  const double target_kg = target_g / 1000.0;
  plant.command_valve(sim::ValveCommand::open);
  double previous_released = 0.0;
  bool closed = false;
  for (std::uint32_t j = 0; j < kMaxJiffies; ++j) {
    plant.advance(kJiffyS);
    const sim::PlantTruth& t = plant.truth();
    if (!closed) {
      const double flow = (t.released_kg - previous_released) / kJiffyS;
      previous_released = t.released_kg;
      const double now = t.released_kg + flow * let_through_s;
      closed = close_within_jiffy(plant, now, flow, target_kg);
    } else if (landed_and_shut(t)) {
      return limit_result(t);
    }
  }
  return Fill{};
}

// The limit of a perfect scale: what oracle_fill reads, but only what has landed. Each jiffy it
// reads, exactly, the static mass, the landing rate and the pile top; never the mass in flight,
// the released mass or the silo. The material in flight it must predict as the landing rate times
// the fall time from the present pile top, plus the valve's let-through like oracle_fill; it closes
// within the jiffy when static + that prediction reaches the target. The stream it sees landing
// left the orifice a fall time (~0.45 s) ago, so the silo's flow fluctuation since then, which
// oracle_fill reads and it cannot, is what separates the two limits.
// Before the first grain lands it knows nothing and keeps the valve open: targets smaller than
// what is in flight when the stream lands are not its purpose.
Fill oracle_scale_fill(const sim::Scene& scene, std::uint64_t seed, double target_g) {
  sim::Plant plant(scene, seed);
  const double let_through_s = true_let_through_s(scene);
  const double bore_area_m2 = model::bore_area_m2(scene.silo.bore_m);
  const double target_kg = target_g / 1000.0;
  plant.command_valve(sim::ValveCommand::open);
  // The static mass of the last kLandingWindowJiffies jiffies, oldest first.
  std::array<double, kLandingWindowJiffies + 1> landed_kg{};
  std::array<double, kLandingWindowJiffies + 1> fall_m{};
  fall_m.fill(plant.truth().fall_height_m);
  std::uint32_t landing_jiffies = 0;
  bool closed = false;
  for (std::uint32_t j = 0; j < kMaxJiffies; ++j) {
    plant.advance(kJiffyS);
    const sim::PlantTruth& t = plant.truth();
    if (!closed) {
      std::rotate(landed_kg.begin(), landed_kg.begin() + 1, landed_kg.end());
      landed_kg.back() = t.static_kg;
      std::rotate(fall_m.begin(), fall_m.begin() + 1, fall_m.end());
      fall_m.back() = t.fall_height_m;
      if (t.static_kg <= 0.0) continue;  // nothing has landed: keep open
      const std::uint32_t landed_jiffies = std::min(++landing_jiffies, kLandingWindowJiffies);
      const std::size_t oldest = kLandingWindowJiffies - landed_jiffies;
      const double window_s = landed_jiffies * kJiffyS;
      const double landing_kg_s = (landed_kg.back() - landed_kg[oldest]) / window_s;
      const double h = t.fall_height_m;
      const double rise_m_s = (fall_m[oldest] - h) / window_s;  // the pile top coming up
      if (landing_kg_s <= 0.0) continue;
      // The pile top rising into the stream makes material land faster than it leaves the orifice
      // (v / (v + u), as model::predict_final); two passes, as there, since v depends on the flow.
      double release_kg_s = landing_kg_s;
      double v0 = 0.0;
      for (int pass = 0; pass < 2; ++pass) {
        v0 = model::outflow_speed(release_kg_s, bore_area_m2, scene.silo.bulk_density);
        const double v = model::impact_speed(v0, scene.g, h);
        release_kg_s = landing_kg_s * v / (v + std::max(0.0, rise_m_s));
      }
      const double in_flight_kg = release_kg_s * model::fall_time(v0, scene.g, h);
      const double now = t.static_kg + in_flight_kg + release_kg_s * let_through_s;
      closed = close_within_jiffy(plant, now, release_kg_s, target_kg);
    } else if (landed_and_shut(t)) {
      return limit_result(t);
    }
  }
  return Fill{};
}

// The engineer's tuning of a fixed preact: a few trial fills with none, then the mean overshoot.
void tune_preact(const Scenario& scenario, BenchStrategy strategy, double target_g,
                 firmware::PersistentSettings& settings) {
  const auto id = strategy == BenchStrategy::preact ? firmware::ParameterId::preact_g
                                                    : firmware::ParameterId::twostage_preact_g;
  settings.parameters.set(id, 0.0f);
  double overshoot = 0.0;
  std::uint32_t counted = 0;
  for (std::uint32_t i = 0; i < kTrialFills; ++i) {
    firmware::PersistentSettings trial = settings;
    const Fill f = indicator_fill(scenario.scene, kTrialSeedBase + i, strategy, target_g, trial);
    if (!f.ok) continue;
    overshoot += f.true_fill_g - target_g;
    ++counted;
  }
  // A single-stage preact closes before the target; a two-stage fine cutoff may have to close after it
  // (its reading can run ahead of what has fallen).
  const double tuned = overshoot / counted;
  if (counted) settings.parameters.set(id, float(strategy == BenchStrategy::preact ? std::max(0.0, tuned) : tuned));
}

}  // namespace

const char* bench_strategy_name(BenchStrategy strategy) { return kNames[static_cast<int>(strategy)]; }

bool parse_bench_strategy(const std::string& name, BenchStrategy& strategy) {
  for (std::size_t i = 0; i < std::size(kNames); ++i) {
    if (name == kNames[i]) {
      strategy = static_cast<BenchStrategy>(i);
      return true;
    }
  }
  return false;
}

double physical_minimum_s(const sim::Scene& scene, double target_g) {
  const sim::Plant plant(scene, 1);
  const double flow = plant.full_open_rate_kg_s();
  const double v0 = model::outflow_speed(flow, model::bore_area_m2(scene.silo.bore_m), scene.silo.bulk_density);
  return scene.valve.dead_time_s + target_g / 1000.0 / flow + model::fall_time(v0, scene.g, scene.column.fall_height_m);
}

sim::Scene scene_for_fill(const Scenario& scenario, std::size_t fill_index, std::size_t fills) {
  sim::Scene scene = scenario.scene;
  if (scenario.material_change && fill_index >= fills / 2) {
    scene.silo.bulk_density *= 0.85;  // a lighter, slower-flowing material
    scene.silo.beverloo_C *= 0.9;
  }
  return scene;
}

namespace {
// The series' knob and certification.
void set_strategy_knob(const SeriesSpec& spec, const sim::Plant& reference, firmware::PersistentSettings& settings) {
  if (is_two_stage(spec.strategy)) {
    const double band_g = spec.knob * reference.full_open_rate_kg_s() * 1000.0;
    settings.parameters.set(firmware::ParameterId::twostage_band_g, float(band_g));
  }
  if (spec.strategy == BenchStrategy::model || spec.strategy == BenchStrategy::learn) {
    settings.parameters.set(firmware::ParameterId::model_fine_s, float(spec.knob));
  }
  if (spec.strategy == BenchStrategy::twostage_dyn) {
    settings.parameters.set(firmware::ParameterId::certify, float(firmware::CertifyMode::dynamic));
  }
}

// The installation values and the series' knob and certification.
firmware::PersistentSettings series_settings(const SeriesSpec& spec, const Scenario& scenario) {
  const sim::Plant reference(scenario.scene, 1);
  firmware::PersistentSettings settings = installation(scenario, reference);
  set_strategy_knob(spec, reference, settings);
  return settings;
}
}  // namespace

void set_up_strategy(const SeriesSpec& spec, const Scenario& scenario, firmware::PersistentSettings& settings) {
  set_strategy_knob(spec, sim::Plant(scenario.scene, 1), settings);
  if (spec.strategy == BenchStrategy::preact || is_two_stage(spec.strategy)) {
    tune_preact(scenario, spec.strategy, spec.target_g, settings);
  }
}

std::vector<double> fills_from_defaults(const SeriesSpec& spec, const Scenario& scenario, std::uint32_t fills) {
  firmware::PersistentSettings settings = series_settings(spec, scenario);
  std::vector<double> errors;
  for (std::uint32_t s = 1; s <= fills; ++s) {
    const Fill f = indicator_fill(scene_for_fill(scenario, s - 1, fills), s, spec.strategy, spec.target_g, settings);
    errors.push_back(f.ok ? f.true_fill_g - spec.target_g : std::nan(""));
  }
  return errors;
}

SeriesResult run_series(const SeriesSpec& spec, const Scenario& scenario, std::uint32_t seeds) {
  SeriesResult result;
  result.spec = spec;
  firmware::PersistentSettings settings = series_settings(spec, scenario);
  const bool two_stage = is_two_stage(spec.strategy);
  if (spec.strategy == BenchStrategy::preact || two_stage) tune_preact(scenario, spec.strategy, spec.target_g, settings);
  const bool learns_by_itself = spec.strategy == BenchStrategy::learn || spec.strategy == BenchStrategy::pac ||
                                spec.strategy == BenchStrategy::flowpreact;
  if (two_stage || learns_by_itself) {
    for (std::uint32_t i = 0; i < kWarmUpFills; ++i) {
      indicator_fill(scenario.scene, kTrialSeedBase + 100 + i, spec.strategy, spec.target_g, settings);
    }
  }

  const double t_phys = physical_minimum_s(scenario.scene, spec.target_g);
  std::vector<double> errors;
  for (std::uint32_t s = 1; s <= seeds; ++s) {
    const sim::Scene scene = scene_for_fill(scenario, s - 1, seeds);
    const Fill f = spec.strategy == BenchStrategy::oracle         ? oracle_fill(scene, s, spec.target_g)
                   : spec.strategy == BenchStrategy::oracle_scale ? oracle_scale_fill(scene, s, spec.target_g)
                                                                  : indicator_fill(scene, s, spec.strategy,
                                                                                   spec.target_g, settings);
    ++result.fills;
    if (!f.ok) {
      ++result.failed;
      continue;
    }
    errors.push_back(f.true_fill_g - spec.target_g);
    const double ratio = f.time_s / t_phys;
    result.time_ratio_mean += ratio;
    result.time_ratio_max = std::max(result.time_ratio_max, ratio);
    result.worst_reported_vs_true_g = std::max(result.worst_reported_vs_true_g, std::abs(f.reported_fill_g - f.true_fill_g));
  }
  if (errors.empty()) return result;
  const double n = double(errors.size());
  result.time_ratio_mean /= n;
  for (double e : errors) result.bias_g += e / n;
  for (double e : errors) {
    result.sd_g += (e - result.bias_g) * (e - result.bias_g);
    result.max_deviation_g = std::max(result.max_deviation_g, std::abs(e - result.bias_g));
  }
  result.sd_g = errors.size() > 1 ? std::sqrt(result.sd_g / (n - 1.0)) : 0.0;
  result.oiml_class = result.failed ? 0.0 : model::best_oiml_class(spec.target_g, result.max_deviation_g, result.bias_g);
  return result;
}

}  // namespace dynweigh::tools
