#pragma once
// The load cell, valve and gate ports of the host board, wired to an in-process plant. Lockstep: the
// plant advances one jiffy per control-loop iteration, as fast as the CPU allows.
#include "dynweigh/firmware/persistent_settings.hpp"
#include "dynweigh/hal/ports.hpp"
#include "dynweigh/sim/plant.hpp"

namespace dynweigh::hal::host {

class SimulatedLoadCell final : public LoadCellPort {
 public:
  explicit SimulatedLoadCell(sim::Plant& plant) : plant_(plant) {}
  firmware::LoadCellInput read_sample() override;

 private:
  sim::Plant& plant_;
};

class SimulatedValve final : public ValvePort {
 public:
  SimulatedValve(sim::Plant& plant, double jiffy_s) : plant_(plant), jiffy_s_(jiffy_s) {}
  void command(firmware::ValveCommand command, std::uint8_t delay_100us) override;
  firmware::ValvePosition position() const override;

 private:
  sim::Plant& plant_;
  double jiffy_s_;
};

// The plant's discharge gate: commands and feedback at once (its module has no sub-jiffy delay).
class SimulatedGate final : public GatePort {
 public:
  explicit SimulatedGate(sim::Plant& plant) : plant_(plant) {}
  void command(firmware::GateCommand command) override;
  firmware::GatePosition position() const override;

 private:
  sim::Plant& plant_;
};

// The plant's ingredient valves 1.. (its scene's `ingredients`), timed within the jiffy as the valve is.
class SimulatedIngredientValves final : public IngredientValvesPort {
 public:
  SimulatedIngredientValves(sim::Plant& plant, double jiffy_s) : plant_(plant), jiffy_s_(jiffy_s) {}
  std::uint8_t present() const override;
  void command(std::uint8_t ingredient, firmware::ValveCommand command, std::uint8_t delay_100us) override;
  firmware::ValvePosition position(std::uint8_t ingredient) const override;

 private:
  sim::Plant& plant_;
  double jiffy_s_;
};

// An indicator freshly calibrated to this plant (docs/programs.md: "starts calibrated to the simulated plant").
firmware::PersistentSettings factory_settings(const sim::Plant& plant);

}  // namespace dynweigh::hal::host
