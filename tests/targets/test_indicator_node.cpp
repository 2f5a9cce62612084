// The portable CAN indicator node (hal/can/indicator_node.hpp) against a scripted link and console:
// no transport, no clock, no plant. Each test feeds frames and jiffies without a sample as a board
// would and reads back the frames the node sent and what the indicator says on its console.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/hal/can/indicator_node.hpp"
#include "dynweigh/hal/can/protocol.hpp"

namespace dynweigh::testing {
namespace {

namespace can = hal::can;
using Heard = can::IndicatorNode::Heard;

class ScriptedLink final : public can::CanLink {
 public:
  void send(const can::CanFrame& frame) override { sent.push_back(frame); }
  bool bus_off() const override { return off; }

  std::vector<can::CanFrame> take() {
    std::vector<can::CanFrame> frames;
    frames.swap(sent);
    return frames;
  }

  std::vector<can::CanFrame> sent;
  bool off = false;
};

class ScriptedConsole final : public hal::ConsolePort {
 public:
  std::size_t read(char* destination, std::size_t capacity) override {
    const std::size_t n = input.copy(destination, capacity);
    input.erase(0, n);
    return n;
  }
  void write(const char* data, std::size_t length) override { output.append(data, length); }

  std::string input, output;
};

can::CanFrame sample(std::uint16_t counter, std::int32_t raw_counts = 100000) {
  return can::encode(can::LoadCellSampleMessage{raw_counts, counter, 0});
}

can::CanFrame heartbeat_of(std::uint8_t node, std::uint8_t nmt_state) {
  return can::encode(can::HeartbeatMessage{node, nmt_state});
}

struct Reply {
  can::ValveCommandMessage valve;
  can::IndicatorStatusMessage status;
};

// The frames of one answered jiffy: exactly a 0x220, then a 0x181.
Reply reply_of(const std::vector<can::CanFrame>& frames) {
  Reply reply;
  EXPECT_EQ(frames.size(), 2u);
  if (frames.size() != 2) return reply;
  EXPECT_TRUE(can::decode(frames[0], reply.valve)) << "first frame 0x" << std::hex << frames[0].id;
  EXPECT_TRUE(can::decode(frames[1], reply.status)) << "second frame 0x" << std::hex << frames[1].id;
  return reply;
}

class IndicatorNodeTest : public ::testing::Test {
 protected:
  explicit IndicatorNodeTest(std::uint32_t heartbeat_jiffies = 0)
      : node_(indicator_, console_, link_, can::IndicatorNodeOptions{nullptr, heartbeat_jiffies, nullptr}) {}

  // What `status` says now (it runs in a jiffy without a sample, as a silent link would give).
  std::string status_after(std::uint16_t next_counter) {
    console_.output.clear();
    console_.input = "status\n";
    node_.receive(sample(next_counter));
    node_.receive(sample(std::uint16_t(next_counter + 1)));
    return console_.output;
  }

  firmware::Indicator indicator_{firmware::PersistentSettings{}};
  ScriptedConsole console_;
  ScriptedLink link_;
  can::IndicatorNode node_;
};

TEST_F(IndicatorNodeTest, EachSampleRunsOneJiffyAnsweredByOneValveCommandThenTheStatusWithItsCounter) {
  for (std::uint16_t counter = 7; counter < 12; ++counter) {
    ASSERT_EQ(node_.receive(sample(counter)), Heard::sample);
    const Reply reply = reply_of(link_.take());
    EXPECT_EQ(reply.valve.counter, counter);
    EXPECT_EQ(reply.status.counter, counter);
    EXPECT_EQ(reply.valve.command, std::uint8_t(firmware::ValveCommand::closed));
  }
  EXPECT_EQ(node_.jiffy(), 5u);
  EXPECT_EQ(node_.last_outputs().answered_counter, 11u);
}

TEST_F(IndicatorNodeTest, LostSamplesAreJiffiesWithoutAnAnswer) {
  ASSERT_EQ(node_.receive(sample(1)), Heard::sample);
  link_.take();
  ASSERT_EQ(node_.receive(sample(5)), Heard::sample);  // 2, 3 and 4 lost
  EXPECT_EQ(node_.jiffy(), 5u);                         // one jiffy for each
  EXPECT_EQ(node_.samples().lost(), 3u);
  EXPECT_EQ(reply_of(link_.take()).valve.counter, 5u);  // only the sample that came is answered
}

TEST_F(IndicatorNodeTest, DuplicateAndLateSamplesRunNoJiffyAndAreNotAnswered) {
  ASSERT_EQ(node_.receive(sample(5)), Heard::sample);
  ASSERT_EQ(node_.receive(sample(6)), Heard::sample);
  link_.take();
  EXPECT_EQ(node_.receive(sample(6)), Heard::repeated_sample);
  EXPECT_EQ(node_.receive(sample(5)), Heard::repeated_sample);
  EXPECT_EQ(node_.jiffy(), 2u);
  EXPECT_TRUE(link_.sent.empty());
  EXPECT_EQ(node_.samples().duplicates(), 1u);
  EXPECT_EQ(node_.samples().out_of_order(), 1u);
}

TEST_F(IndicatorNodeTest, AJiffyWithoutASampleIsAnsweredAndASilentLinkBecomesTheSilenceFault) {
  ASSERT_EQ(node_.receive(sample(1)), Heard::sample);
  link_.take();
  node_.run_without_sample();
  const Reply stood_in = reply_of(link_.take());
  EXPECT_EQ(stood_in.status.state, std::uint8_t(firmware::IndicatorState::idle));
  for (int i = 0; i < 20; ++i) node_.run_without_sample();  // nothing at all from the plant
  const std::vector<can::CanFrame> frames = link_.take();
  ASSERT_EQ(frames.size(), 40u);
  can::IndicatorStatusMessage last;
  ASSERT_TRUE(can::decode(frames.back(), last));
  EXPECT_EQ(last.state, std::uint8_t(firmware::IndicatorState::fault));
  EXPECT_NE(status_after(2).find("fault=can_silence"), std::string::npos) << console_.output;
}

TEST_F(IndicatorNodeTest, APlantThatSpeaksWithoutSamplesIsAStaleLoadCellNotASilentLink) {
  ASSERT_EQ(node_.receive(sample(1)), Heard::sample);
  for (int i = 0; i < 20; ++i) {
    EXPECT_EQ(node_.receive(heartbeat_of(can::kNodeValve, can::kNmtOperational)), Heard::ignored);
    node_.run_without_sample();
  }
  EXPECT_NE(status_after(2).find("fault=stale_sample"), std::string::npos) << console_.output;
}

TEST_F(IndicatorNodeTest, OurOwnFramesEchoedByTheBusAreNotThePlant) {
  ASSERT_EQ(node_.receive(sample(1)), Heard::sample);
  const std::vector<can::CanFrame> own = link_.take();
  for (int i = 0; i < 20; ++i) {
    for (const can::CanFrame& frame : own) EXPECT_EQ(node_.receive(frame), Heard::ignored);
    EXPECT_EQ(node_.receive(heartbeat_of(can::kNodeIndicator, can::kNmtOperational)), Heard::ignored);
    node_.run_without_sample();
  }
  EXPECT_NE(status_after(2).find("fault=can_silence"), std::string::npos) << console_.output;
}

TEST_F(IndicatorNodeTest, ABusOffTransportIsAFaultInTheJiffyItIsFound) {
  ASSERT_EQ(node_.receive(sample(1)), Heard::sample);
  link_.take();
  link_.off = true;
  node_.run_without_sample();
  EXPECT_EQ(reply_of(link_.take()).status.state, std::uint8_t(firmware::IndicatorState::fault));
  link_.off = false;
  EXPECT_NE(status_after(2).find("fault=bus_off"), std::string::npos) << console_.output;
}

TEST_F(IndicatorNodeTest, APlantThatStopsInOrderIsCountedAfreshWhenItComesBack) {
  ASSERT_EQ(node_.receive(sample(40)), Heard::sample);
  EXPECT_TRUE(node_.plant_heard());
  EXPECT_EQ(node_.receive(heartbeat_of(can::kNodeLoadCell, can::kNmtStopped)), Heard::plant_stopped);
  link_.take();
  ASSERT_EQ(node_.receive(sample(30)), Heard::sample);  // else late, and dropped
  EXPECT_EQ(reply_of(link_.take()).valve.counter, 30u);
  EXPECT_EQ(node_.samples().lost(), 0u);
}

TEST_F(IndicatorNodeTest, TheValvePositionAndMalformedFramesAreNotJiffies) {
  EXPECT_EQ(node_.receive(can::encode(can::ValveFeedbackMessage{3, 0})), Heard::valve_position);
  can::CanFrame short_sample = sample(1);
  short_sample.dlc = 4;
  EXPECT_EQ(node_.receive(short_sample), Heard::ignored);
  EXPECT_EQ(node_.jiffy(), 0u);
  EXPECT_TRUE(link_.sent.empty());
}

// The gate module's fault bits (0x1A8 byte 1): any set is the fault gate_fault, in the next jiffy.
TEST_F(IndicatorNodeTest, AFaultTheGateModuleReportsIsTheGateFault) {
  ASSERT_EQ(node_.receive(sample(1)), Heard::sample);
  EXPECT_EQ(node_.receive(can::encode(can::GateFeedbackMessage{0, 0})), Heard::gate_position);
  ASSERT_EQ(node_.receive(sample(2)), Heard::sample);
  EXPECT_EQ(indicator_.fault(), firmware::Fault::none);
  EXPECT_EQ(node_.receive(can::encode(can::GateFeedbackMessage{0, 0x04})), Heard::gate_position);
  link_.take();
  ASSERT_EQ(node_.receive(sample(3)), Heard::sample);
  EXPECT_EQ(indicator_.fault(), firmware::Fault::gate_fault);
  const Reply reply = reply_of(link_.take());
  EXPECT_EQ(reply.valve.command, std::uint8_t(firmware::ValveCommand::closed));
  EXPECT_EQ(reply.status.state, std::uint8_t(firmware::IndicatorState::fault));
  EXPECT_NE(status_after(4).find("fault=gate_fault"), std::string::npos);
}

TEST_F(IndicatorNodeTest, LeavingSaysNmtStopped) {
  ASSERT_EQ(node_.receive(sample(1)), Heard::sample);
  link_.take();
  node_.leave();  // the valve is closed: no 0x220 needed
  ASSERT_EQ(link_.sent.size(), 1u);
  can::HeartbeatMessage said;
  ASSERT_TRUE(can::decode(link_.sent[0], said));
  EXPECT_EQ(said.node, can::kNodeIndicator);
  EXPECT_EQ(said.nmt_state, can::kNmtStopped);
}

class IndicatorNodeWithHeartbeat : public IndicatorNodeTest {
 protected:
  IndicatorNodeWithHeartbeat() : IndicatorNodeTest(10) {}
};

TEST_F(IndicatorNodeWithHeartbeat, AHeartbeatFollowsEveryTenthJiffysAnswer) {
  for (std::uint16_t counter = 1; counter <= 20; ++counter) {
    ASSERT_EQ(node_.receive(sample(counter)), Heard::sample);
    const std::vector<can::CanFrame> frames = link_.take();
    ASSERT_EQ(frames.size(), counter % 10 == 0 ? 3u : 2u) << "jiffy " << counter;
    if (counter % 10 != 0) continue;
    can::HeartbeatMessage said;
    ASSERT_TRUE(can::decode(frames[2], said));
    EXPECT_EQ(said.nmt_state, can::kNmtOperational);
  }
}

}  // namespace
}  // namespace dynweigh::testing
