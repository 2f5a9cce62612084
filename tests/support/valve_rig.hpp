#pragma once
// An indicator and an in-process plant in lockstep, with the valve's feedback as a chosen valve
// module gives it: `moving` through the stroke (the plant's), or the end positions only (limit
// switches: the last end position until the next is reached). The valve can be made to stick where
// it is from the next close command on; the rig records that close and the jiffy the indicator first
// reported a fault.
#include <cstdint>
#include <string>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/hal/control_loop.hpp"
#include "dynweigh/hal/host/simulated_plant_ports.hpp"
#include "dynweigh/sim/plant.hpp"
#include "dynweigh/sim/scene.hpp"
#include "support/string_console.hpp"

namespace dynweigh::testing {

enum class ValveFeedbackKind { reports_moving, end_positions_only };

class ValveUnderTest final : public hal::ValvePort {
 public:
  ValveUnderTest(hal::ValvePort& inner, ValveFeedbackKind kind) : inner_(inner), kind_(kind) {}

  void command(firmware::ValveCommand command, std::uint8_t delay_100us) override {
    const bool new_close = command == firmware::ValveCommand::closed && previous_ != firmware::ValveCommand::closed;
    previous_ = command;
    if (stuck_) return;
    if (stick_at_close_ && new_close) {
      stuck_ = true;
      ignored_close_delay_100us_ = delay_100us;
      return;
    }
    inner_.command(command, delay_100us);
  }

  firmware::ValvePosition position() const override {
    const firmware::ValvePosition p = inner_.position();
    if (kind_ == ValveFeedbackKind::reports_moving) return p;
    if (p != firmware::ValvePosition::moving) last_end_ = p;
    return last_end_;
  }

  void stick_at_next_close() { stick_at_close_ = true; }
  bool stuck() const { return stuck_; }
  std::uint8_t ignored_close_delay_100us() const { return ignored_close_delay_100us_; }

 private:
  hal::ValvePort& inner_;
  ValveFeedbackKind kind_;
  firmware::ValveCommand previous_ = firmware::ValveCommand::closed;
  bool stick_at_close_ = false;
  bool stuck_ = false;
  std::uint8_t ignored_close_delay_100us_ = 0;
  mutable firmware::ValvePosition last_end_ = firmware::ValvePosition::closed;
};

class ValveRig {
 public:
  static constexpr double kJiffyS = 0.010;

  ValveRig(const sim::Scene& scene, ValveFeedbackKind kind, std::uint64_t seed = 1)
      : plant_(scene, seed),
        cell_(plant_),
        plant_valve_(plant_, kJiffyS),
        valve_(plant_valve_, kind),
        indicator_(hal::host::factory_settings(plant_)) {}

  // Sends one command line and runs until its answer ends (OK or ERR) or `max_jiffies` pass.
  std::string run_command(const std::string& line, std::uint32_t max_jiffies = 9000) {
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
    const bool was_stuck = valve_.stuck();
    hal::Ports ports{cell_, valve_, console_, nullptr};
    const firmware::Outputs out = hal::run_one_jiffy(indicator_, ports, jiffy_).outputs;
    if (!was_stuck && valve_.stuck()) ignored_close_jiffy_ = jiffy_;
    if (!detected_ && indicator_.fault() != firmware::Fault::none) {
      detected_ = true;
      detection_jiffy_ = jiffy_;
    }
    plant_.advance(kJiffyS);
    ++jiffy_;
    return out;
  }

  sim::Plant& plant() { return plant_; }
  firmware::Indicator& indicator() { return indicator_; }
  ValveUnderTest& valve() { return valve_; }
  bool detected() const { return detected_; }
  // Seconds from the moment a healthy valve of the scene's timing would have shut after the close
  // the stuck valve ignored, to the jiffy whose feedback the fault was found on.
  double detection_after_healthy_shut_s() const {
    const sim::ValveParameters& v = plant_.scene().valve;
    const double close_acts_s = ignored_close_jiffy_ * kJiffyS + valve_.ignored_close_delay_100us() * 1e-4;
    return detection_jiffy_ * kJiffyS - (close_acts_s + v.dead_time_s + v.full_stroke_s);
  }

 private:
  sim::Plant plant_;
  hal::host::SimulatedLoadCell cell_;
  hal::host::SimulatedValve plant_valve_;
  ValveUnderTest valve_;
  firmware::Indicator indicator_;
  StringConsole console_;
  std::uint32_t jiffy_ = 0;
  bool detected_ = false;
  std::uint32_t detection_jiffy_ = 0;
  std::uint32_t ignored_close_jiffy_ = 0;
};

}  // namespace dynweigh::testing
