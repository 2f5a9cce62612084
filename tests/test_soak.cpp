// The soak: one indicator doses cycle after cycle, random targets and strategies, with a
// random fault injected into a third of the cycles at a random jiffy. Each cycle gets a fresh
// hopper (a new plant, as a discharged hopper), the indicator carries on. Nothing may hang, every
// fault must be answered and cleared, and no fill may exceed its target by more than the OIML R61
// X(1) in-service limit, except where a stuck-open valve was injected, which must alarm within
// 100 ms of the close it ignored. DYNWEIGH_SOAK_CYCLES sets the number of cycles (10,000).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/hal/control_loop.hpp"
#include "dynweigh/hal/host/fault_injection.hpp"
#include "dynweigh/hal/host/simulated_plant_ports.hpp"
#include "dynweigh/model/oiml_r61_class.hpp"
#include "dynweigh/sim/plant.hpp"
#include "dynweigh/sim/random.hpp"
#include "dynweigh/sim/scene.hpp"
#include "support/string_console.hpp"

namespace dynweigh::testing {
namespace {

using hal::host::SensorFault;
using hal::host::SensorFaultPlan;
using hal::host::ValveFault;

constexpr double kJiffyS = 0.010;
// Longer than the firmware's own dose timeout (120 s): a dose that has not answered by then hangs.
constexpr std::uint32_t kAnswerWithinJiffies = 13'000;
constexpr std::uint32_t kLandingJiffies = 300;  // after the answer, whatever still flows lands
constexpr std::uint32_t kEmptyHopperJiffies = 100;

struct InjectedFault {
  const char* name = "none";
  SensorFaultPlan sensor{};
  ValveFault valve = ValveFault::none;
  std::uint32_t valve_at = 0;
};

InjectedFault random_fault(sim::Random& random) {
  const auto at = std::uint32_t(random.uniform() * 800.0);  // a few land in the empty-hopper second
  switch (int(random.uniform() * 9.0)) {
    case 0: return {"spike", {SensorFault::spike, at, 1, random.uniform() < 0.5 ? 8000 : -8000, 0}};
    case 1: return {"spike_burst", {SensorFault::spike, at, 1 + std::uint32_t(random.uniform() * 20), 8000, 0}};
    case 2: return {"freeze", {SensorFault::freeze, at, 0xFFFFFFFFu, 0, 0}};
    case 3: return {"saturate", {SensorFault::saturate, at, 0xFFFFFFFFu, 0, 0x7FFFFF}};
    case 4: return {"silence", {SensorFault::silence, at, 1 + std::uint32_t(random.uniform() * 400), 0, 0}};
    case 5: return {"valve_stuck", {}, ValveFault::stuck, at};
    case 6: return {"valve_stuck_lying_closed", {}, ValveFault::stuck_lying_closed, at};
    case 7: return {"valve_stuck_lying_echo", {}, ValveFault::stuck_lying_echo, at};
    default: return {"valve_stuck_at_start", {}, ValveFault::stuck, 0};
  }
}

// The hopper, valve and load cell of one cycle, with the cycle's faults wired in.
struct CyclePlant {
  CyclePlant(std::uint64_t seed, const InjectedFault& f)
      : plant(sim::default_scene(), seed),
        cell(plant),
        valve(plant, kJiffyS),
        faulty_cell(cell, f.sensor),
        faulty_valve(valve, faulty_cell, f.valve, f.valve_at) {}
  sim::Plant plant;
  hal::host::SimulatedLoadCell cell;
  hal::host::SimulatedValve valve;
  hal::host::FaultyLoadCell faulty_cell;
  hal::host::FaultyValve faulty_valve;
};

struct CycleOutcome {
  bool answered = false;
  std::string answer;
  double final_g = 0;
  bool faulted = false;
  bool stuck_open_injected = false;
  bool alarm_in_time = true;
};

class SoakStation {
 public:
  SoakStation() : indicator_(hal::host::factory_settings(sim::Plant(sim::default_scene(), 1))) {}

  CycleOutcome run_cycle(std::uint64_t seed, const InjectedFault& fault, const std::string& dose) {
    CyclePlant p(seed, fault);
    CycleOutcome outcome;
    console_.pending.clear();
    console_.output.clear();
    std::uint32_t jiffy = 0, close_jiffy = 0, alarm_jiffy = 0;
    bool valve_was_open = false, closed_after_open = false, alarmed = false;
    auto step = [&] {
      hal::Ports ports{p.faulty_cell, p.faulty_valve, console_, nullptr};
      const firmware::Outputs out = hal::run_one_jiffy(indicator_, ports, jiffy).outputs;
      if (out.valve != firmware::ValveCommand::closed) valve_was_open = true;
      if (valve_was_open && !closed_after_open && out.valve == firmware::ValveCommand::closed) {
        closed_after_open = true;
        close_jiffy = jiffy;
      }
      if (!alarmed && indicator_.fault() != firmware::Fault::none) {
        alarmed = true;
        alarm_jiffy = jiffy;
      }
      p.plant.advance(kJiffyS);
      ++jiffy;
      return out;
    };
    // The hopper was emptied: the indicator watches the empty hopper for a second before the dose.
    for (std::uint32_t i = 0; i < kEmptyHopperJiffies; ++i) step();
    console_.pending = dose + "\n";
    for (std::uint32_t i = 0; i < kAnswerWithinJiffies; ++i) {
      const firmware::Outputs out = step();
      if (console_.pending.empty() && !out.busy && answered(console_.output)) {
        outcome.answered = true;
        break;
      }
    }
    for (std::uint32_t i = 0; i < kLandingJiffies; ++i) step();
    outcome.answer = console_.output;
    outcome.final_g = p.plant.truth().static_kg * 1000.0;
    outcome.faulted = indicator_.fault() != firmware::Fault::none;
    // Stuck open: the valve took the fault while the stream ran, and then ignored the close.
    outcome.stuck_open_injected = p.faulty_valve.injected() && p.plant.truth().stroke > 0.0;
    if (outcome.stuck_open_injected) {
      // A valve that reports its true position alarms from its feedback within 100 ms; one whose
      // feedback lies can only be found by the weight that keeps coming after the rest-drop.
      const bool honest_feedback = fault.valve == ValveFault::stuck;
      outcome.alarm_in_time = alarmed && (!honest_feedback || (closed_after_open && alarm_jiffy >= close_jiffy &&
                                                               alarm_jiffy - close_jiffy <= 10));
    }
    return outcome;
  }

  std::string command(const std::string& line) {
    console_.pending = line + "\n";
    console_.output.clear();
    sim::Plant idle_plant(sim::default_scene(), 1);
    hal::host::SimulatedLoadCell cell(idle_plant);
    hal::host::SimulatedValve valve(idle_plant, kJiffyS);
    for (std::uint32_t jiffy = 0; jiffy < 200; ++jiffy) {
      hal::Ports ports{cell, valve, console_, nullptr};
      const firmware::Outputs out = hal::run_one_jiffy(indicator_, ports, jiffy).outputs;
      idle_plant.advance(kJiffyS);
      if (console_.pending.empty() && !out.busy && answered(console_.output)) break;
    }
    return console_.output;
  }

  firmware::Indicator& indicator() { return indicator_; }

 private:
  static bool answered(const std::string& text) {
    if (text.empty() || text.back() != '\n') return false;
    return text.rfind("RESULT", 0) == 0 || text.rfind("ERR ", 0) == 0 ||
           text.find("\nRESULT") != std::string::npos || text.find("\nERR ") != std::string::npos;
  }

  firmware::Indicator indicator_;
  StringConsole console_;
};

std::uint64_t soak_cycles() {
  const char* text = std::getenv("DYNWEIGH_SOAK_CYCLES");
  return text ? std::strtoull(text, nullptr, 10) : 10'000;
}

TEST(Soak, TenThousandCyclesWithRandomFaults) {
  const std::uint64_t cycles = soak_cycles();
  const char* const strategies[] = {"model", "learn", "twostage", "preact"};
  sim::Random random(2026);
  SoakStation station;
  std::map<std::string, int> injected_by_kind;
  std::map<std::string, int> faults_raised;
  std::uint64_t overdoses = 0, hangs = 0, stuck_open = 0, results = 0;
  double worst_excess_g = -1e9;
  for (std::uint64_t cycle = 0; cycle < cycles; ++cycle) {
    const char* strategy = strategies[int(random.uniform() * 4.0)];
    // 5..15 kg: where every strategy meets X(1) on the default scene in `dynweigh bench`. Below, at
    // 2.4 kg/s, about 1.2 kg is in the air when the valve closes: the baselines cannot fill there and
    // the model closes on its prior (the bench reports X(5)..X(20) at 2..3 kg).
    const int target_g = 5000 + int(random.uniform() * 10000.0);
    const InjectedFault fault = random.uniform() < 1.0 / 3.0 ? random_fault(random) : InjectedFault{};
    ++injected_by_kind[fault.name];
    const std::string dose = "dose " + std::to_string(target_g) + " " + strategy;
    const CycleOutcome o = station.run_cycle(cycle + 1, fault, dose);
    SCOPED_TRACE("cycle " + std::to_string(cycle) + ": " + dose + " with " + fault.name + " from jiffy " +
                 std::to_string(fault.valve == ValveFault::none ? fault.sensor.at_jiffy : fault.valve_at));
    if (!o.answered) ++hangs;
    ASSERT_TRUE(o.answered) << o.answer;
    if (o.answer.find("RESULT") != std::string::npos) ++results;
    if (o.stuck_open_injected) {
      ++stuck_open;
      EXPECT_TRUE(o.alarm_in_time) << "a stuck-open valve must alarm (within 100 ms of the close when its "
                                      "feedback tells the truth)\n"
                                   << o.answer;
    } else {
      const double excess_g = o.final_g - target_g;
      worst_excess_g = std::max(worst_excess_g, excess_g);
      if (excess_g > model::oiml_x1_limits(target_g).in_service_g) {
        ++overdoses;
        ADD_FAILURE() << "overdose: " << o.final_g << " g\n" << o.answer;
      }
    }
    if (o.faulted) {
      ++faults_raised[firmware::fault_name(station.indicator().fault())];
      EXPECT_EQ(station.command("dose 1000"), "ERR 4 fault active\n");  // latched
      ASSERT_EQ(station.command("clearfault"), "OK\n");
    }
    ASSERT_EQ(station.indicator().fault(), firmware::Fault::none) << firmware::fault_name(station.indicator().fault());
  }
  std::printf("soak: %llu cycles, %llu results, %llu hangs, %llu overdoses, %llu stuck open (alarmed), "
              "worst excess over target outside stuck-open %.1f g\n",
              static_cast<unsigned long long>(cycles), static_cast<unsigned long long>(results),
              static_cast<unsigned long long>(hangs), static_cast<unsigned long long>(overdoses),
              static_cast<unsigned long long>(stuck_open), worst_excess_g);
  std::printf("injected:");
  for (const auto& [name, n] : injected_by_kind) std::printf(" %s=%d", name.c_str(), n);
  std::printf("\nraised:");
  for (const auto& [name, n] : faults_raised) std::printf(" %s=%d", name.c_str(), n);
  std::printf("\n");
  EXPECT_EQ(overdoses, 0u);
  EXPECT_EQ(hangs, 0u);
}

}  // namespace
}  // namespace dynweigh::testing
