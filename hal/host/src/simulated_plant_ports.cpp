#include "dynweigh/hal/host/simulated_plant_ports.hpp"

#include <cmath>

namespace dynweigh::hal::host {

firmware::LoadCellInput SimulatedLoadCell::read_sample() {
  const sim::LoadCellSample sample = plant_.sample();
  firmware::LoadCellInput input;
  input.raw_counts = sample.raw_counts;
  input.counter = sample.counter;
  input.status = sample.status;
  input.fresh = true;
  return input;
}

void SimulatedValve::command(firmware::ValveCommand command, std::uint8_t delay_100us) {
  const double delay_s = delay_100us < jiffy_s_ * 1e4 ? delay_100us * 1e-4 : 0.0;
  plant_.command_valve(command, delay_s);
}

firmware::ValvePosition SimulatedValve::position() const {
  return plant_.valve_feedback();
}

std::uint8_t SimulatedIngredientValves::present() const {
  const std::size_t n = plant_.ingredient_count();
  return std::uint8_t((1u << (n < 8 ? n : 8)) - 1u);
}

// A scene without ingredients has no valves here: nothing is commanded, nothing changes.
void SimulatedIngredientValves::command(std::uint8_t ingredient, firmware::ValveCommand command, std::uint8_t delay_100us) {
  const double delay_s = delay_100us < jiffy_s_ * 1e4 ? delay_100us * 1e-4 : 0.0;
  for (std::size_t i = 1; i < plant_.ingredient_count(); ++i) {
    if (i == ingredient) {
      plant_.command_ingredient_valve(i, command, delay_s);
    } else {
      plant_.command_ingredient_valve(i, firmware::ValveCommand::closed);
    }
  }
}

firmware::ValvePosition SimulatedIngredientValves::position(std::uint8_t ingredient) const {
  return plant_.ingredient_valve_feedback(ingredient);
}

void SimulatedGate::command(firmware::GateCommand command) {
  plant_.command_gate(command == firmware::GateCommand::open ? sim::GateCommand::open : sim::GateCommand::closed);
}

firmware::GatePosition SimulatedGate::position() const {
  return firmware::GatePosition{static_cast<std::uint8_t>(plant_.gate_feedback())};
}

firmware::PersistentSettings factory_settings(const sim::Plant& plant) {
  firmware::PersistentSettings settings;
  const double empty_counts = plant.empty_counts();
  settings.calibration.zero_counts = std::int32_t(std::floor(empty_counts));
  settings.calibration.zero_fraction = float(empty_counts - std::floor(empty_counts));
  settings.calibration.counts_per_gram = float(plant.counts_per_gram());
  settings.calibration.zero_set = true;
  settings.calibration.span_set = true;
  // The commissioning tap test: the platform's frequency with what is on it when the scale reads
  // zero (the empty container; in the hourglass, the loaded silo too).
  const sim::Scene& scene = plant.scene();
  const bool rings = plant.components().has(sim::Component::platform);
  const double at_zero_kg = scene.platform.container_kg +
                            (scene.hourglass.enabled ? scene.hourglass.silo_tare_kg + scene.silo.fill_kg : 0.0);
  const double at_zero_hz = scene.platform.natural_hz * std::sqrt(scene.platform.container_kg / at_zero_kg);
  settings.parameters.set(firmware::ParameterId::platform_hz, rings ? float(at_zero_hz) : 0.0f);
  if (rings) settings.parameters.set(firmware::ParameterId::platform_kg, float(at_zero_kg));
  return settings;
}

}  // namespace dynweigh::hal::host
