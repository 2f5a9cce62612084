#pragma once
// The plant: silo -> valve -> falling column -> pile -> impact -> platform -> load cell, plus the
// pile top, avalanches, creep and the hourglass configuration where a scene asks for them. Only
// the components the scene runs (components_of) are built and stepped. Stepped at the scene's
// internal rate under the indicator's 10 ms jiffy; the step loop does not allocate.
//
// Every force the platform receives is the exact mean over the step of a piecewise model:
// parcels leave the silo at their release instant and land at their exact landing instant,
// momentum arrives with the landing speed consistent with the time in the air. So mass is
// conserved at every step and the hourglass' impulse balance holds to rounding.
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "dynweigh/sim/components.hpp"
#include "dynweigh/sim/discharge_gate.hpp"
#include "dynweigh/sim/falling_column.hpp"
#include "dynweigh/sim/impact_relaxation.hpp"
#include "dynweigh/sim/load_cell.hpp"
#include "dynweigh/sim/pile.hpp"
#include "dynweigh/sim/pile_avalanches.hpp"
#include "dynweigh/sim/pneumatic_valve.hpp"
#include "dynweigh/sim/scale_platform.hpp"
#include "dynweigh/sim/scene.hpp"
#include "dynweigh/sim/silo.hpp"

namespace dynweigh::sim {

// One ingredient's stream (a scene without ingredients has only ingredient 0).
struct IngredientTruth {
  double released_kg = 0.0;     // out of its silo since the start
  double silo_kg = 0.0;         // still in its silo
  double refilled_kg = 0.0;     // poured into its silo from upstream since the start
  double in_flight_kg = 0.0;    // between its orifice and the pile
  double stroke = 0.0;          // its valve, 0 shut .. 1 open
};

// The plant's own view, which no indicator sees: the truth a fill is judged against.
struct PlantTruth {
  double time_s = 0.0;
  double released_kg = 0.0;
  double static_kg = 0.0;       // landed and at rest on the scale
  double in_flight_kg = 0.0;
  double force_n = 0.0;         // load-cell force above the empty container's weight (hourglass:
                                // above the loaded rest weight of silo, fill and container)
  double impact_force_n = 0.0;  // mean over the last step, avalanches included
  double stroke = 0.0;
  double fall_height_m = 0.0;   // orifice to the present pile top
  double silo_kg = 0.0;         // still in the silo
  double refilled_kg = 0.0;     // poured into the silo from upstream since the start
  bool refilling = false;       // the upstream feeder runs
  double discharged_kg = 0.0;   // emptied out of the hopper through the discharge gate
  double gate_stroke = 0.0;     // 0 shut .. 1 open
  double force_impulse_n_s = 0.0;  // exact time integral of force_n since the start
  std::uint64_t avalanches = 0;
  // Per ingredient, in valve order: the totals above (released, silo, refilled, in flight) are their
  // sums; stroke above is ingredient 0's.
  std::array<IngredientTruth, kMaxIngredients> ingredients{};
};

class Plant {
 public:
  Plant(const Scene& scene, std::uint64_t seed);

  // A command reaches the valve `delay_s` after the present instant; repeats are ignored.
  void command_valve(ValveCommand command, double delay_s = 0.0);
  void advance(double seconds);
  // A test weight set down on the platform at once (0: lifted off): a load beside the fill, as an
  // integrator adjusts the span with (`cal`). The platform rings from it; it is not in static_kg.
  void place_test_weight(double kg) { test_weight_kg_ = kg; }
  LoadCellSample sample() { return load_cell_.convert(support_force_n(), truth_.time_s); }

  // Upstream supply (plant commands, beside the scene's automatic refill below
  // silo.refill_below_kg): `kg` poured in at once, or a refill up to silo.fill_kg at
  // silo.refill_rate_kg_s.
  void add_to_silo(double kg);
  void start_refill() { truth_.refilling = true; }

  // The discharge gate under the hopper (at once: its module has no sub-jiffy delay).
  void command_gate(GateCommand command) { gate_.command(command); }
  GateFeedback gate_feedback() const { return gate_.feedback(); }
  // A jammed gate holds its stroke whatever it is told (a fault to supervise).
  void jam_gate(bool jammed) { gate_.jam(jammed); }

  // The ingredients' valves (docs/scenes.md, `ingredients`): ingredient 0 is the valve above.
  // False, and nothing happens, for an ingredient the scene does not have.
  std::size_t ingredient_count() const { return 1 + extra_.size(); }
  bool command_ingredient_valve(std::size_t ingredient, ValveCommand command, double delay_s = 0.0);
  ValvePosition ingredient_valve_feedback(std::size_t ingredient) const;

  const PlantTruth& truth() const { return truth_; }
  ValvePosition valve_feedback() const { return valve_.feedback(); }
  const Scene& scene() const { return scene_; }

  // Factory calibration of an indicator to this plant: counts of the empty container (hourglass:
  // of the loaded rest weight), and gain.
  double empty_counts() const;
  double counts_per_gram() const { return load_cell_.counts_per_gram(); }
  double full_open_rate_kg_s() const { return silo_.full_open_rate_kg_s(); }

  // What the plant runs, and how often each component has been stepped (for "only what a scene
  // needs": a component not built is never stepped).
  const ComponentSet& components() const { return components_; }
  std::uint64_t component_steps(Component component) const;
  std::uint64_t steps() const { return steps_; }

 private:
  void step();
  void refill_step();
  double discharge_step(double dt);
  double fall_height_m();
  // Ingredients 1.. (ingredient 0 is valve_, silo_, column_): each its own stream, landing on the
  // same pile from its own height.
  struct ExtraStream {
    ExtraStream(const IngredientParameters& p, double g, std::size_t capacity, std::uint64_t seed);
    IngredientParameters parameters;
    PneumaticValve valve;
    Silo silo;
    FallingColumn column;
    ValveCommand last_command = ValveCommand::closed;
    bool refilling = false;
  };
  struct Release {
    double weighted_kg_s = 0.0;  // sum of mass times its time off the silo in the step
    double momentum_n_s = 0.0;
  };
  Release release_step(Silo& silo, PneumaticValve& valve, FallingColumn& column, double begin, double end,
                       double& own_released_kg);
  void refill_extra(ExtraStream& stream, IngredientTruth& truth);
  double support_force_n() const { return platform_ ? platform_->support_force_n() : rigid_support_force_n_; }

  Scene scene_;
  ComponentSet components_;
  double dt_;
  double reference_weight_n_;  // what force_n is measured from
  PneumaticValve valve_;
  DischargeGate gate_;
  Silo silo_;
  FallingColumn column_;
  std::optional<Pile> pile_;
  std::optional<ImpactRelaxation> impact_;
  std::optional<PileAvalanches> avalanches_;
  std::optional<ScalePlatform> platform_;
  std::vector<ExtraStream> extra_;
  LoadCell load_cell_;
  double rigid_support_force_n_;
  double test_weight_kg_ = 0.0;
  ValveCommand last_command_ = ValveCommand::closed;
  std::uint64_t steps_ = 0;
  PlantTruth truth_;
};

}  // namespace dynweigh::sim
