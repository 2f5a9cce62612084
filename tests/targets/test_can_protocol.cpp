// The CAN frame codec (docs/can-protocol.md): byte layout, round trips, and the frames a decoder must refuse.
#include <gtest/gtest.h>

#include "dynweigh/hal/can/protocol.hpp"

namespace dynweigh::hal::can {
namespace {

TEST(CanProtocol, LoadCellSampleIsLittleEndianWithCounterAndStatus) {
  const CanFrame f = encode(LoadCellSampleMessage{-2, 0x1234, 0x05});
  EXPECT_EQ(f.id, 0x190u);
  ASSERT_EQ(f.dlc, 8);
  const std::uint8_t expected[8] = {0xFE, 0xFF, 0xFF, 0xFF, 0x34, 0x12, 0x05, 0x00};
  for (int i = 0; i < 8; ++i) EXPECT_EQ(f.data[i], expected[i]) << i;
  LoadCellSampleMessage m;
  ASSERT_TRUE(decode(f, m));
  EXPECT_EQ(m.raw_counts, -2);
  EXPECT_EQ(m.counter, 0x1234);
  EXPECT_EQ(classify(f), MessageKind::load_cell_sample);
}

TEST(CanProtocol, ValveCommandCarriesDelayAndAnsweredCounter) {
  const CanFrame f = encode(ValveCommandMessage{2, 37, 0xBEEF});
  EXPECT_EQ(f.id, 0x220u);
  ASSERT_EQ(f.dlc, 4);
  EXPECT_EQ(f.data[0], 2);
  EXPECT_EQ(f.data[1], 37);
  EXPECT_EQ(f.data[2], 0xEF);
  EXPECT_EQ(f.data[3], 0xBE);
  ValveCommandMessage m;
  ASSERT_TRUE(decode(f, m));
  EXPECT_EQ(m.command, 2);
  EXPECT_EQ(m.delay_100us, 37);
  EXPECT_EQ(m.counter, 0xBEEF);
}

TEST(CanProtocol, ValveCommandDelayIsClampedTo99OnEncodeAndRefusedAboveOnDecode) {
  EXPECT_EQ(encode(ValveCommandMessage{1, 200, 0}).data[1], 99);
  CanFrame f = encode(ValveCommandMessage{1, 0, 0});
  f.data[1] = 100;
  ValveCommandMessage m{7, 7, 7};
  EXPECT_FALSE(decode(f, m));
  EXPECT_EQ(m.command, 7);  // untouched
  f.data[1] = 0;
  f.data[0] = 3;  // no such command
  EXPECT_FALSE(decode(f, m));
}

TEST(CanProtocol, ValveFeedbackStatusAndHeartbeatRoundTrip) {
  ValveFeedbackMessage fb;
  ASSERT_TRUE(decode(encode(ValveFeedbackMessage{3, 0x40}), fb));
  EXPECT_EQ(fb.position, 3);
  EXPECT_EQ(fb.faults, 0x40);
  EXPECT_EQ(encode(ValveFeedbackMessage{}).id, 0x1A0u);

  IndicatorStatusMessage st;
  const CanFrame status = encode(IndicatorStatusMessage{-12345, 2, 1, 999});
  EXPECT_EQ(status.id, 0x181u);
  ASSERT_TRUE(decode(status, st));
  EXPECT_EQ(st.weight_100mg, -12345);
  EXPECT_EQ(st.state, 2);
  EXPECT_EQ(st.valve, 1);
  EXPECT_EQ(st.counter, 999);

  const CanFrame beat = encode(HeartbeatMessage{kNodeIndicator, kNmtOperational});
  EXPECT_EQ(beat.id, 0x701u);
  EXPECT_EQ(beat.dlc, 1);
  EXPECT_EQ(beat.data[0], 0x05);
  HeartbeatMessage hb;
  ASSERT_TRUE(decode(beat, hb));
  EXPECT_EQ(hb.node, 1);
  EXPECT_EQ(classify(encode(HeartbeatMessage{kNodeValve, kNmtOperational})), MessageKind::heartbeat);
}

TEST(CanProtocol, WrongDlcIsRefused) {
  LoadCellSampleMessage sample;
  CanFrame f = encode(LoadCellSampleMessage{1, 2, 0});
  f.dlc = 7;
  EXPECT_FALSE(decode(f, sample));
  ValveCommandMessage command;
  CanFrame c = encode(ValveCommandMessage{1, 0, 5});
  c.dlc = 8;
  EXPECT_FALSE(decode(c, command));
  c.dlc = 3;
  EXPECT_FALSE(decode(c, command));
  HeartbeatMessage beat;
  CanFrame h = encode(HeartbeatMessage{1, 5});
  h.dlc = 0;
  EXPECT_FALSE(decode(h, beat));
}

TEST(CanProtocol, UnknownExtendedAndRemoteFramesAreRefused) {
  CanFrame unknown;
  unknown.id = 0x123;
  unknown.dlc = 8;
  EXPECT_EQ(classify(unknown), MessageKind::unknown);
  LoadCellSampleMessage sample;
  EXPECT_FALSE(decode(unknown, sample));  // a decoder checks the identifier itself

  CanFrame extended = encode(LoadCellSampleMessage{});
  extended.extended = true;
  EXPECT_EQ(classify(extended), MessageKind::unknown);
  EXPECT_FALSE(decode(extended, sample));

  CanFrame remote = encode(LoadCellSampleMessage{});
  remote.remote = true;
  EXPECT_FALSE(decode(remote, sample));

  CanFrame nmt;  // 0x700 itself is no node's heartbeat
  nmt.id = 0x700;
  nmt.dlc = 1;
  EXPECT_EQ(classify(nmt), MessageKind::unknown);
}

TEST(CanProtocol, LinuxCanFrameBytesMatchTheKernelLayout) {
  const CanFrame f = encode(ValveCommandMessage{1, 5, 0x0102});
  std::uint8_t bytes[kLinuxFrameSize];
  to_linux_bytes(f, bytes);
  const std::uint8_t expected[16] = {0x20, 0x02, 0, 0, 4, 0, 0, 0, 1, 5, 0x02, 0x01, 0, 0, 0, 0};
  for (unsigned i = 0; i < kLinuxFrameSize; ++i) EXPECT_EQ(bytes[i], expected[i]) << i;
  CanFrame back;
  ASSERT_TRUE(from_linux_bytes(bytes, kLinuxFrameSize, back));
  EXPECT_EQ(back, f);

  CanFrame ext;
  ext.id = 0x1ABCDEF0;
  ext.extended = true;
  ext.dlc = 0;
  to_linux_bytes(ext, bytes);
  EXPECT_EQ(bytes[3], 0x80 | 0x1A);
  ASSERT_TRUE(from_linux_bytes(bytes, kLinuxFrameSize, back));
  EXPECT_TRUE(back.extended);
  EXPECT_EQ(back.id, 0x1ABCDEF0u);
}

TEST(CanProtocol, MalformedLinuxFramesAreRefused) {
  std::uint8_t bytes[kLinuxFrameSize] = {0x90, 0x01, 0, 0, 9};  // len 9
  CanFrame f;
  EXPECT_FALSE(from_linux_bytes(bytes, kLinuxFrameSize, f));
  bytes[4] = 8;
  EXPECT_FALSE(from_linux_bytes(bytes, kLinuxFrameSize - 1, f));  // short datagram
  bytes[3] = 0x20;  // error frame flag
  EXPECT_FALSE(from_linux_bytes(bytes, kLinuxFrameSize, f));
  bytes[3] = 0;
  bytes[1] = 0x08;  // 0x890: standard id out of 11 bits
  EXPECT_FALSE(from_linux_bytes(bytes, kLinuxFrameSize, f));
}

}  // namespace
}  // namespace dynweigh::hal::can

namespace dynweigh::hal::can {
namespace {

// The discharge gate (node 0x28): 0x228 command (0 closed, 2 open; byte 1 zero; the sample's
// counter), 0x1A8 feedback (0 closed, 1 moving, 3 open; fault bits).
TEST(CanProtocol, DischargeGateFramesAreLaidOutAsTheNodeExpects) {
  const CanFrame command = encode(GateCommandMessage{2, 0x0304});
  EXPECT_EQ(command.id, 0x228u);
  EXPECT_EQ(command.dlc, 4);
  EXPECT_EQ(command.data[0], 2);
  EXPECT_EQ(command.data[1], 0);
  EXPECT_EQ(command.data[2], 0x04);
  EXPECT_EQ(command.data[3], 0x03);
  EXPECT_EQ(classify(command), MessageKind::gate_command);
  GateCommandMessage c;
  ASSERT_TRUE(decode(command, c));
  EXPECT_EQ(c.command, 2);
  EXPECT_EQ(c.counter, 0x0304);

  const CanFrame feedback = encode(GateFeedbackMessage{3, 0x01});
  EXPECT_EQ(feedback.id, 0x1A8u);
  EXPECT_EQ(feedback.dlc, 2);
  EXPECT_EQ(classify(feedback), MessageKind::gate_feedback);
  GateFeedbackMessage f;
  ASSERT_TRUE(decode(feedback, f));
  EXPECT_EQ(f.position, 3);
  EXPECT_EQ(f.faults, 1);
}

TEST(CanProtocol, DischargeGateRefusesAHalfPositionAndWrongShapes) {
  CanFrame half = encode(GateCommandMessage{2, 1});
  half.data[0] = 1;
  GateCommandMessage c;
  EXPECT_FALSE(decode(half, c));
  CanFrame long_command = encode(GateCommandMessage{0, 1});
  long_command.dlc = 8;
  EXPECT_FALSE(decode(long_command, c));
  CanFrame half_feedback = encode(GateFeedbackMessage{0, 0});
  half_feedback.data[0] = 2;
  GateFeedbackMessage f;
  EXPECT_FALSE(decode(half_feedback, f));
  ValveCommandMessage valve;
  EXPECT_FALSE(decode(encode(GateCommandMessage{2, 1}), valve));  // another node's frame
}

}  // namespace
}  // namespace dynweigh::hal::can
