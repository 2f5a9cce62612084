#pragma once
// The plant of the default scene: silo -> valve -> falling column -> pile -> impact -> platform ->
// load cell, stepped at the scene's internal rate under the indicator's 10 ms jiffy.
#include <cstdint>

#include "dynweigh/model/pile_geometry.hpp"
#include "dynweigh/sim/falling_column.hpp"
#include "dynweigh/sim/impact_relaxation.hpp"
#include "dynweigh/sim/load_cell.hpp"
#include "dynweigh/sim/pneumatic_valve.hpp"
#include "dynweigh/sim/scale_platform.hpp"
#include "dynweigh/sim/scene.hpp"
#include "dynweigh/sim/silo.hpp"

namespace dynweigh::sim {

// The plant's own view, which no indicator sees: the truth a fill is judged against.
struct PlantTruth {
  double time_s = 0.0;
  double released_kg = 0.0;
  double static_kg = 0.0;       // landed and at rest on the scale
  double in_flight_kg = 0.0;
  double force_n = 0.0;         // load-cell force above the empty container's weight
  double impact_force_n = 0.0;
  double stroke = 0.0;
  double fall_height_m = 0.0;   // orifice to the present pile top
};

class Plant {
 public:
  Plant(const Scene& scene, std::uint64_t seed);

  // A command reaches the valve `delay_s` after the present instant; repeats are ignored.
  void command_valve(ValveCommand command, double delay_s = 0.0);
  void advance(double seconds);
  LoadCellSample sample() { return load_cell_.convert(platform_.support_force_n()); }

  const PlantTruth& truth() const { return truth_; }
  ValveFeedback valve_feedback() const { return valve_.feedback(); }
  const Scene& scene() const { return scene_; }

  // Factory calibration of an indicator to this plant: counts of the empty container, and gain.
  double empty_counts() const;
  double counts_per_gram() const { return load_cell_.counts_per_gram(); }
  double full_open_rate_kg_s() const { return silo_.full_open_rate_kg_s(); }

 private:
  void step(double dt);
  double current_fall_height_m() const;

  Scene scene_;
  model::PileGeometry<double> pile_;
  PneumaticValve valve_;
  Silo silo_;
  FallingColumn column_;
  ImpactRelaxation impact_;
  ScalePlatform platform_;
  LoadCell load_cell_;
  ValveCommand last_command_ = ValveCommand::closed;
  std::uint64_t steps_ = 0;
  PlantTruth truth_;
};

}  // namespace dynweigh::sim
