#pragma once
// Fault injection at the driver edge (ArduPilot SITL's habit): wrappers around a LoadCellPort and a
// ValvePort that break the way real hardware does, from a chosen jiffy on. Each read_sample() call
// is one jiffy (the control loop reads one sample per jiffy); the valve follows the load cell's clock.
#include <cstdint>

#include "dynweigh/hal/ports.hpp"

namespace dynweigh::hal::host {

enum class SensorFault : std::uint8_t {
  none,
  freeze,    // the value sticks at the last good one; the counter keeps counting
  spike,     // `spike_counts` added for `duration` jiffies
  saturate,  // the converter pegs at `saturated_counts` with the overload bit
  silence,   // no sample arrives (fresh = false)
};

enum class ValveFault : std::uint8_t {
  none,
  stuck,               // ignores every command; reports its true position
  stuck_lying_closed,  // ignores every command; reports closed whatever it does
  stuck_lying_echo,    // ignores every command; reports the commanded position (a dead gate, no flow)
};

struct SensorFaultPlan {
  SensorFault fault = SensorFault::none;
  std::uint32_t at_jiffy = 0;
  std::uint32_t duration = 0xFFFFFFFFu;  // jiffies; spikes usually last 1
  std::int32_t spike_counts = 0;
  std::int32_t saturated_counts = 0x7FFFFF;
};

class FaultyLoadCell final : public LoadCellPort {
 public:
  FaultyLoadCell(LoadCellPort& inner, SensorFaultPlan plan) : inner_(inner), plan_(plan) {}
  firmware::LoadCellInput read_sample() override {
    firmware::LoadCellInput s = inner_.read_sample();
    const std::uint32_t j = jiffy_++;
    const bool active = plan_.fault != SensorFault::none && j >= plan_.at_jiffy && j - plan_.at_jiffy < plan_.duration;
    if (!active) {
      last_good_ = s.raw_counts;
      return s;
    }
    if (!injected_) injected_at_ = j;
    injected_ = true;
    switch (plan_.fault) {
      case SensorFault::none: break;
      case SensorFault::freeze: s.raw_counts = last_good_; break;
      case SensorFault::spike: s.raw_counts += plan_.spike_counts; break;
      case SensorFault::saturate:
        s.raw_counts = plan_.saturated_counts;
        s.status |= firmware::kLoadCellOverload;
        break;
      case SensorFault::silence: s.fresh = false; break;
    }
    return s;
  }
  std::uint32_t jiffy() const { return jiffy_; }
  bool injected() const { return injected_; }
  std::uint32_t injected_at() const { return injected_at_; }

 private:
  LoadCellPort& inner_;
  SensorFaultPlan plan_;
  std::uint32_t jiffy_ = 0;
  std::int32_t last_good_ = 0;
  bool injected_ = false;
  std::uint32_t injected_at_ = 0;
};

class FaultyValve final : public ValvePort {
 public:
  // `clock` tells the jiffy (the load cell wrapper of the same board).
  FaultyValve(ValvePort& inner, const FaultyLoadCell& clock, ValveFault fault, std::uint32_t at_jiffy)
      : inner_(inner), clock_(clock), fault_(fault), at_jiffy_(at_jiffy) {}
  void command(firmware::ValveCommand command, std::uint8_t delay_100us) override {
    commanded_ = command;
    // The command of jiffy j is applied after read_sample() of jiffy j counted it: clock_ is j + 1.
    if (active()) {
      if (!injected_) injected_at_ = clock_.jiffy() - 1;
      injected_ = true;
      return;
    }
    inner_.command(command, delay_100us);
  }
  firmware::ValvePosition position() const override {
    if (!injected_) return inner_.position();
    switch (fault_) {
      case ValveFault::stuck_lying_closed: return firmware::ValvePosition::closed;
      case ValveFault::stuck_lying_echo:
        return commanded_ == firmware::ValveCommand::open   ? firmware::ValvePosition::open
               : commanded_ == firmware::ValveCommand::half ? firmware::ValvePosition::half
                                                            : firmware::ValvePosition::closed;
      case ValveFault::none:
      case ValveFault::stuck: break;
    }
    return inner_.position();
  }
  bool injected() const { return injected_; }
  std::uint32_t injected_at() const { return injected_at_; }

 private:
  bool active() const { return fault_ != ValveFault::none && clock_.jiffy() > at_jiffy_; }

  ValvePort& inner_;
  const FaultyLoadCell& clock_;
  ValveFault fault_;
  std::uint32_t at_jiffy_;
  firmware::ValveCommand commanded_ = firmware::ValveCommand::closed;
  bool injected_ = false;
  std::uint32_t injected_at_ = 0;
};

}  // namespace dynweigh::hal::host
