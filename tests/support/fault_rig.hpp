#pragma once
// An indicator and an in-process plant in lockstep, with the fault-injecting port wrappers
// (hal/host/fault_injection.hpp) between them; drives the console one command at a time and
// records when a fault was first detected and what the valve was told in that jiffy.
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/hal/control_loop.hpp"
#include "dynweigh/hal/host/fault_injection.hpp"
#include "dynweigh/hal/host/simulated_plant_ports.hpp"
#include "dynweigh/sim/plant.hpp"
#include "dynweigh/sim/scene.hpp"
#include "support/string_console.hpp"

namespace dynweigh::testing {

class FaultRig {
 public:
  static constexpr double kJiffyS = 0.010;

  FaultRig(hal::host::SensorFaultPlan sensor, hal::host::ValveFault valve, std::uint32_t valve_at,
           const sim::Scene& scene = sim::default_scene(), std::uint64_t seed = 1)
      : plant_(scene, seed),
        cell_(plant_),
        valve_(plant_, kJiffyS),
        faulty_cell_(cell_, sensor),
        faulty_valve_(valve_, faulty_cell_, valve, valve_at),
        indicator_(hal::host::factory_settings(plant_)) {}

  // Sends one command line and runs until its answer ends (OK or ERR) or `max_jiffies` pass.
  std::string run_command(const std::string& line, std::uint32_t max_jiffies = 200) {
    console_.pending = line + "\n";
    console_.output.clear();
    for (std::uint32_t i = 0; i < max_jiffies; ++i) {
      const firmware::Outputs out = step();
      if (console_.pending.empty() && !out.busy && ends_with_answer(console_.output)) break;
    }
    return console_.output;
  }

  void idle(std::uint32_t jiffies) {
    for (std::uint32_t i = 0; i < jiffies; ++i) step();
  }

  firmware::Outputs step() {
    hal::Ports ports{faulty_cell_, faulty_valve_, console_, nullptr};
    const firmware::Outputs out = hal::run_one_jiffy(indicator_, ports, jiffy_).outputs;
    if (!detected_ && indicator_.fault() != firmware::Fault::none) {
      detected_ = true;
      detection_jiffy_ = jiffy_;
      valve_at_detection_ = out.valve;
    }
    if (faulty_valve_.injected() && !closed_after_injection_ && out.valve == firmware::ValveCommand::closed) {
      closed_after_injection_ = true;
      close_jiffy_ = jiffy_;
    }
    plant_.advance(kJiffyS);
    ++jiffy_;
    return out;
  }

  sim::Plant& plant() { return plant_; }
  firmware::Indicator& indicator() { return indicator_; }
  std::uint32_t jiffy() const { return jiffy_; }  // the fault plans count from the rig's start
  const std::string& output() const { return console_.output; }  // since the last command was sent
  bool detected() const { return detected_; }
  std::uint32_t detection_jiffy() const { return detection_jiffy_; }
  firmware::ValveCommand valve_at_detection() const { return valve_at_detection_; }
  // The first close command after the valve fault took hold (the close the stuck valve ignored).
  bool closed_after_injection() const { return closed_after_injection_; }
  std::uint32_t close_jiffy() const { return close_jiffy_; }

 private:

  sim::Plant plant_;
  hal::host::SimulatedLoadCell cell_;
  hal::host::SimulatedValve valve_;
  hal::host::FaultyLoadCell faulty_cell_;
  hal::host::FaultyValve faulty_valve_;
  firmware::Indicator indicator_;
  StringConsole console_;
  std::uint32_t jiffy_ = 0;
  bool detected_ = false;
  std::uint32_t detection_jiffy_ = 0;
  firmware::ValveCommand valve_at_detection_ = firmware::ValveCommand::closed;
  bool closed_after_injection_ = false;
  std::uint32_t close_jiffy_ = 0;
};

inline std::vector<std::string> rig_lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

}  // namespace dynweigh::testing
