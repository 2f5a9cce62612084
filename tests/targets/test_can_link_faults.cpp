// CAN link faults over the in-process udp loopback: the indicator on the Linux CAN board,
// the simulated plant as the modules of docs/can-protocol.md, the fault-injecting transport between them
// (tests/support/can_fault_rig.hpp). Dropped, duplicated and reordered frames must leave a dose
// within one jiffy of flow of the healthy one; a silent bus and a bus-off must close the valve in
// the jiffy they are found, name themselves in `status`, refuse `dose` with ERR 4, stay latched
// until `clearfault` and show in the test-data record. The plant's mass is the measure.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "support/can_fault_rig.hpp"
#include "support/fault_rig.hpp"

namespace dynweigh::testing {
namespace {

using firmware::Fault;
using hal::linux_can::CanFaultPlan;
using hal::linux_can::ChosenFrameFault;
using hal::linux_can::Direction;
using hal::linux_can::FrameFault;
using hal::linux_can::LinkFault;

constexpr std::int32_t kTargetG = 5000;
constexpr std::uint32_t kFaultSample = 60;  // 0.6 s into the dose: the valve is open, the flow runs

// Frames the rig's plant sends in its jiffy k: two heartbeats every tenth jiffy, feedback, sample.
std::uint32_t sample_frame_index(std::uint32_t k) {
  std::uint32_t index = 0;
  for (std::uint32_t j = 0; j <= k; ++j) index += (j % 10 == 0 ? 4u : 2u);
  return index - 1;
}

double fill_g(CanFaultRig& rig) { return rig.plant().truth().static_kg * 1000.0; }

std::string field_of(const std::string& text, const std::string& key) {
  const std::size_t at = text.find(key + "=");
  if (at == std::string::npos) return {};
  const std::size_t start = at + key.size() + 1;
  return text.substr(start, text.find_first_of(" \n", start) - start);
}

TEST(CanLinkFaults, DuplicatedDelayedAndLostSamplesKeepTheIndicatorInStepWithThePlant) {
  CanFaultPlan plan;
  plan.chosen = {{Direction::received, sample_frame_index(20), FrameFault::duplicate},
                 {Direction::received, sample_frame_index(40), FrameFault::drop},
                 {Direction::received, sample_frame_index(60), FrameFault::delay},   // after 1 frame: in order
                 {Direction::received, sample_frame_index(80), FrameFault::duplicate},
                 {Direction::sent, 200, FrameFault::drop},
                 {Direction::sent, 300, FrameFault::duplicate}};
  CanFaultRig rig(plan);
  rig.idle(120);
  EXPECT_EQ(rig.link().received_counts().duplicated, 2u);
  EXPECT_EQ(rig.link().received_counts().dropped, 1u);
  EXPECT_EQ(rig.link().received_counts().delayed, 1u);
  EXPECT_EQ(rig.board().samples().duplicates(), 2u);  // neither counted twice
  EXPECT_EQ(rig.board().samples().lost(), 1u);        // the dropped one: one jiffy without a sample
  EXPECT_EQ(rig.board().samples().out_of_order(), 0u);
  EXPECT_EQ(rig.board().jiffy(), rig.plant_jiffy()) << "the indicator's clock left the plant's";
  EXPECT_EQ(rig.indicator().fault(), Fault::none) << firmware::fault_name(rig.indicator().fault());
}

TEST(CanLinkFaults, ASampleOvertakenByTheNextIsDiscardedAndTheOneBeforeItMadeUp) {
  CanFaultPlan plan;
  plan.delay_frames = 3;  // held past the next jiffy's feedback and sample
  plan.chosen = {{Direction::received, sample_frame_index(33), FrameFault::delay}};
  CanFaultRig rig(plan);
  rig.idle(60);
  EXPECT_EQ(rig.board().samples().out_of_order(), 1u);
  EXPECT_EQ(rig.board().samples().lost(), 1u);
  EXPECT_EQ(rig.board().jiffy(), rig.plant_jiffy());
  EXPECT_EQ(rig.indicator().fault(), Fault::none);
}

// (a) 1 % of the frames each way dropped, 1 % duplicated, 1 % swapped with the next, seeded.
TEST(CanLinkFaults, RandomDropsDuplicatesAndReordersLeaveTheDoseWithinOneJiffyOfFlowOfTheHealthyOne) {
  for (const char* strategy : {"model", "preact", "twostage"}) {
    SCOPED_TRACE(strategy);
    const std::string command = "dose " + std::to_string(kTargetG) + " " + strategy;
    CanFaultRig healthy(CanFaultPlan{});
    const std::string healthy_answer = healthy.run_command(command, 3000);
    healthy.idle(300);
    ASSERT_NE(healthy_answer.find("RESULT"), std::string::npos) << healthy_answer;
    const double healthy_error_g = fill_g(healthy) - kTargetG;
    // One lost 0x220 at the cutoff lets the valve stay open one jiffy longer (the next answer
    // repeats the close): the most one jiffy of full flow adds, plus one scale division.
    const double tolerance_g = healthy.max_release_per_jiffy_kg() * 1000.0 + 1.0;

    CanFaultPlan plan;
    plan.seed = 7;
    plan.drop_probability = plan.duplicate_probability = plan.reorder_probability = 0.01;
    CanFaultRig rig(plan);
    const std::string answer = rig.run_command(command, 3000);
    rig.idle(300);
    ASSERT_NE(answer.find("RESULT target=5000"), std::string::npos) << answer;
    EXPECT_EQ(rig.indicator().fault(), Fault::none) << firmware::fault_name(rig.indicator().fault());
    const double error_g = fill_g(rig) - kTargetG;
    const auto& in = rig.link().received_counts();
    const auto& out = rig.link().sent_counts();
    std::printf("can_random_faults strategy=%s healthy_error_g=%.1f error_g=%.1f tolerance_g=%.1f "
                "claimed_error_g=%s rx_frames=%u rx_dropped=%u rx_duplicated=%u rx_reordered=%u tx_frames=%u "
                "tx_dropped=%u tx_duplicated=%u tx_reordered=%u samples_lost=%u duplicates_ignored=%u "
                "out_of_order=%u plant_watchdog_closes=%u\n",
                strategy, healthy_error_g, error_g, tolerance_g, field_of(answer, "error").c_str(), in.frames,
                in.dropped, in.duplicated, in.delayed, out.frames, out.dropped, out.duplicated, out.delayed,
                rig.board().samples().lost(), rig.board().samples().duplicates(),
                rig.board().samples().out_of_order(), rig.watchdog_closes());
    EXPECT_GT(in.dropped + in.duplicated + in.delayed + out.dropped + out.duplicated + out.delayed, 20u)
        << "too few faults injected to mean anything";
    EXPECT_LE(std::fabs(error_g), std::fabs(healthy_error_g) + tolerance_g);
  }
}

struct LinkCase {
  const char* name;
  LinkFault fault;
  Fault expected;
};

// (b), (c) and the matrix: a silent bus and a bus-off at sample 60 of a dose, every strategy.
TEST(CanLinkFaultMatrix, SilenceAndBusOffTimesEveryStrategy) {
  int injected = 0;
  for (const LinkCase& c : {LinkCase{"silence", LinkFault::silence, Fault::can_silence},
                            LinkCase{"bus_off", LinkFault::bus_off, Fault::bus_off}}) {
    for (const char* strategy : {"model", "preact", "twostage"}) {
      SCOPED_TRACE(std::string(strategy) + " x " + c.name);
      CanFaultPlan plan;
      plan.link_fault = c.fault;
      plan.link_fault_at_sample = kFaultSample;
      CanFaultRig rig(plan);
      const std::string answer = rig.run_command("dose " + std::to_string(kTargetG) + " " + strategy, 3000);
      ++injected;
      EXPECT_EQ(answer, std::string("ERR 4 fault ") + firmware::fault_name(c.expected) + "\n");
      ASSERT_TRUE(rig.detected());
      ASSERT_TRUE(rig.link_fault_seen());
      EXPECT_EQ(rig.indicator().fault(), c.expected) << firmware::fault_name(rig.indicator().fault());
      EXPECT_EQ(rig.valve_at_detection(), firmware::ValveCommand::closed);
      const std::uint32_t after = rig.detection_jiffy() - rig.link_fault_board_jiffy();
      std::printf("can_link_fault fault=%s strategy=%s onset_jiffy=%u detection_jiffy=%u jiffies_to_detect=%u\n",
                  c.name, strategy, rig.link_fault_board_jiffy(), rig.detection_jiffy(), after);
      if (c.fault == LinkFault::bus_off) {
        EXPECT_EQ(after, 0u) << "bus-off is known at once";
      } else {
        EXPECT_LT(after, 10u) << "silence must be found within the 100 ms stale window";
      }
      const std::string status = rig.run_command("status");
      EXPECT_NE(status.find("state=fault"), std::string::npos) << status;
      EXPECT_NE(status.find(std::string("fault=") + firmware::fault_name(c.expected)), std::string::npos) << status;
      rig.idle(150);  // the valve module's watchdog closed the valve; what was falling lands
      EXPECT_EQ(rig.indicator().fault(), c.expected);  // latched
      EXPECT_EQ(rig.plant().valve_feedback(), sim::ValvePosition::closed);
      EXPECT_LT(fill_g(rig), kTargetG) << "nothing may be overdosed";
      EXPECT_GE(rig.watchdog_closes(), 1u);
      if (std::string(strategy) != "model") continue;
      // Once: a dead link runs the indicator at 10 ms of wall time a jiffy, and a new `dose` has
      // to wait for the 1000-jiffy test-data record of the faulted one to end.
      rig.idle(1000);
      EXPECT_EQ(rig.run_command("dose 1000"), "ERR 4 fault active\n");
      EXPECT_EQ(rig.indicator().fault(), c.expected);
      EXPECT_EQ(rig.run_command("clearfault"), "OK\n");
      rig.idle(30);  // the bus is still dead: the fault comes back by itself
      EXPECT_EQ(rig.indicator().fault(), c.expected) << firmware::fault_name(rig.indicator().fault());
    }
  }
  EXPECT_EQ(injected, 6);
}

// The test-data record shows a bus-off as the valve marker dropping to 0 in the detecting jiffy.
TEST(CanLinkFaults, TestDataRecordShowsABusOffAsValveClosed) {
  CanFaultPlan plan;
  plan.link_fault = LinkFault::bus_off;
  plan.link_fault_at_sample = 900;
  CanFaultRig rig(plan);
  EXPECT_EQ(rig.run_command("starttestdata 50 990"), "OK\n");
  while (rig.board().last_outputs().busy && rig.plant_jiffy() < 1500) rig.step();  // the 1000-jiffy cycle
  ASSERT_TRUE(rig.detected());
  ASSERT_EQ(rig.indicator().fault(), Fault::bus_off);
  const std::vector<std::string> lines = rig_lines_of(rig.run_command("readtestdata", 3000));
  ASSERT_EQ(lines.size(), 1001u);
  std::size_t first_closed = 0;
  for (std::size_t i = 60; i < 1000; ++i) {
    const char marker = lines[i].back();
    if (first_closed == 0 && marker == '0') first_closed = i;
    if (first_closed == 0) {
      EXPECT_EQ(marker, '2') << lines[i];
    } else {
      EXPECT_EQ(marker, '0') << "opened again after the fault: " << lines[i];
    }
  }
  EXPECT_NEAR(double(first_closed), double(rig.detection_jiffy()), 1.0);
  EXPECT_NEAR(double(first_closed), 900.0, 2.0);
  EXPECT_NE(rig.run_command("status").find("fault=bus_off"), std::string::npos);
}

}  // namespace
}  // namespace dynweigh::testing
