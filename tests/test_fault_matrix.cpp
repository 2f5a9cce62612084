// The fault matrix: every injected fault x every strategy. Each fault found closes the
// valve in the jiffy it is detected, `status` names it, `dose` answers ERR 4, the pending dose is
// answered with the fault, and nothing is overdosed beyond target + the OIML R61 X(1) in-service
// limit, except where a stuck-open valve was injected (which alarms within 100 ms of the close).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/hal/control_loop.hpp"
#include "dynweigh/hal/host/fault_injection.hpp"
#include "dynweigh/hal/host/simulated_plant_ports.hpp"
#include "dynweigh/model/oiml_r61_class.hpp"
#include "dynweigh/sim/plant.hpp"
#include "dynweigh/sim/scene.hpp"
#include "support/console_session.hpp"
#include "support/fault_rig.hpp"

namespace dynweigh::testing {
namespace {

using firmware::Fault;
using hal::host::SensorFault;
using hal::host::ValveFault;

constexpr std::int32_t kTargetG = 5000;
constexpr std::uint32_t kRestJiffies = 60;  // the scale stands at rest before the dose, which opens from rest
constexpr std::uint32_t kFaultJiffy = kRestJiffies + 60;  // 0.6 s into the dose: the valve is open, the flow runs

struct MatrixCase {
  const char* name;
  hal::host::SensorFaultPlan sensor;
  ValveFault valve = ValveFault::none;
  std::uint32_t valve_at = 0;
  Fault expected = Fault::none;
  bool stuck_open = false;  // overdose allowed; the alarm must come within 100 ms of the close
};

std::vector<MatrixCase> matrix() {
  using P = hal::host::SensorFaultPlan;
  return {
      {"single_spike_up", P{SensorFault::spike, kFaultJiffy, 1, 8000, 0}, ValveFault::none, 0, Fault::none, false},
      {"single_spike_down", P{SensorFault::spike, kFaultJiffy, 1, -8000, 0}, ValveFault::none, 0, Fault::none,
       false},
      {"spike_burst", P{SensorFault::spike, kFaultJiffy, 3, 8000, 0}, ValveFault::none, 0, Fault::sample_jump,
       false},
      {"sensor_freeze", P{SensorFault::freeze, kFaultJiffy, 0xFFFFFFFFu, 0, 0}, ValveFault::none, 0,
       Fault::sensor_frozen, false},
      {"saturation", P{SensorFault::saturate, kFaultJiffy, 0xFFFFFFFFu, 0, 0x7FFFFF}, ValveFault::none, 0,
       Fault::overload, false},
      {"sensor_silence", P{SensorFault::silence, kFaultJiffy, 0xFFFFFFFFu, 0, 0}, ValveFault::none, 0,
       Fault::stale_sample, false},
      {"valve_stuck_closed", P{}, ValveFault::stuck, 0, Fault::valve_stuck_closed, false},
      {"valve_dead_feedback_echoes", P{}, ValveFault::stuck_lying_echo, 0, Fault::no_flow, false},
      {"valve_stuck_open", P{}, ValveFault::stuck, kFaultJiffy, Fault::valve_stuck_open, true},
      {"valve_stuck_open_feedback_lies", P{}, ValveFault::stuck_lying_echo, kFaultJiffy, Fault::flow_after_close,
       true},
  };
}

TEST(FaultMatrix, EveryFaultTimesEveryStrategy) {
  const double limit_g = model::oiml_x1_limits(kTargetG).in_service_g;
  int injected = 0;
  for (const char* strategy : {"model", "preact", "twostage"}) {
    FaultRig healthy(hal::host::SensorFaultPlan{}, ValveFault::none, 0);
    healthy.idle(kRestJiffies);
    const std::string healthy_answer =
        healthy.run_command("dose " + std::to_string(kTargetG) + " " + strategy, 9000);
    healthy.idle(500);
    const double healthy_g = healthy.plant().truth().static_kg * 1000.0;
    for (const MatrixCase& c : matrix()) {
      SCOPED_TRACE(std::string(strategy) + " x " + c.name);
      FaultRig rig(c.sensor, c.valve, c.valve_at);
      rig.idle(kRestJiffies);
      const std::string answer = rig.run_command("dose " + std::to_string(kTargetG) + " " + strategy, 9000);
      rig.idle(500);  // let whatever is still flowing land
      ++injected;
      const double final_g = rig.plant().truth().static_kg * 1000.0;
      EXPECT_EQ(rig.indicator().fault(), c.expected) << firmware::fault_name(rig.indicator().fault()) << "\n"
                                                     << answer;
      if (c.expected == Fault::none) {
        // A single bogus sample changes nothing: the same cutoff and fill as without it.
        EXPECT_NE(answer.find("RESULT target=5000"), std::string::npos) << answer;
        EXPECT_EQ(field(answer, "cutoff"), field(healthy_answer, "cutoff")) << answer << healthy_answer;
        EXPECT_NEAR(final_g, healthy_g, 1.0);
        EXPECT_LE(final_g, kTargetG + limit_g);
        continue;
      }
      ASSERT_TRUE(rig.detected()) << answer;
      EXPECT_EQ(rig.valve_at_detection(), firmware::ValveCommand::closed);
      EXPECT_EQ(answer, std::string("ERR 4 fault ") + firmware::fault_name(c.expected) + "\n");
      const std::string status = rig.run_command("status");
      EXPECT_NE(status.find("state=fault"), std::string::npos) << status;
      EXPECT_NE(status.find(std::string("fault=") + firmware::fault_name(c.expected)), std::string::npos)
          << status;
      EXPECT_EQ(rig.run_command("dose 1000"), "ERR 4 fault active\n");
      EXPECT_EQ(rig.indicator().fault(), c.expected);  // latched
      if (c.stuck_open) {
        if (c.expected == Fault::valve_stuck_open) {
          ASSERT_TRUE(rig.closed_after_injection());
          EXPECT_LE(rig.detection_jiffy() - rig.close_jiffy(), 10u) << "alarm later than 100 ms after the close";
        }
      } else {
        EXPECT_LE(final_g, std::max(double(kTargetG), healthy_g) + limit_g);
      }
      EXPECT_EQ(rig.run_command("clearfault"), "OK\n");
    }
  }
  EXPECT_EQ(injected, 30);
}

// Nothing injected: the supervisor raises nothing over a series of doses of every strategy.
TEST(FaultMatrix, HealthyDosesRaiseNothing) {
  FaultRig rig(hal::host::SensorFaultPlan{}, ValveFault::none, 0);
  for (const char* strategy : {"model", "preact", "twostage", "model", "preact", "twostage"}) {
    const std::string answer = rig.run_command(std::string("dose 3000 ") + strategy, 9000);
    EXPECT_NE(answer.find("RESULT"), std::string::npos) << strategy << ": " << answer;
    rig.idle(400);
    EXPECT_EQ(rig.indicator().fault(), Fault::none) << firmware::fault_name(rig.indicator().fault());
    EXPECT_EQ(rig.indicator().supervisor().rejected_samples(), 0u);
  }
}

// The test-data record shows the fault: the valve marker drops to 0 at the detection.
TEST(FaultMatrix, TestDataRecordShowsTheFaultAsValveClosed) {
  FaultRig rig(hal::host::SensorFaultPlan{}, ValveFault::stuck, 0);
  EXPECT_EQ(rig.run_command("starttestdata 50 600", 1200), "OK\n");
  ASSERT_EQ(rig.indicator().fault(), Fault::valve_stuck_closed);
  const std::string data = rig.run_command("readtestdata", 3000);
  const auto lines = rig_lines_of(data);
  ASSERT_EQ(lines.size(), 1001u);
  int opened = 0, closed_after = 0;
  for (std::size_t i = 50; i < 600; ++i) {
    const char marker = lines[i].back();
    if (marker == '2') {
      ++opened;
      EXPECT_EQ(closed_after, 0) << "opened again after the fault: " << lines[i];
    } else {
      EXPECT_EQ(marker, '0') << lines[i];
      ++closed_after;
    }
  }
  EXPECT_GE(opened, 1);
  EXPECT_LE(opened, 162);  // detected once the stream had time to land: 30 + 80 + 495 + 1000 ms
  EXPECT_GT(closed_after, 380);
  EXPECT_NE(rig.run_command("status").find("fault=valve_stuck_closed"), std::string::npos);
}

}  // namespace
}  // namespace dynweigh::testing
