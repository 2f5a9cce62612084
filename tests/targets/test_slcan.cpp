// SLCAN (Lawicel) framing: the lines slcand and USB-CAN adapters exchange, and the garbage a
// serial line delivers.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "dynweigh/hal/can/protocol.hpp"
#include "dynweigh/hal/can/slcan.hpp"

namespace dynweigh::hal::can {
namespace {

std::string line_of(const CanFrame& f) {
  char buffer[kSlcanMaxLine];
  const std::size_t n = slcan_encode(f, buffer, sizeof buffer);
  return std::string(buffer, n);
}

std::vector<CanFrame> feed(SlcanDecoder& decoder, const std::string& text) {
  std::vector<CanFrame> frames;
  CanFrame f;
  for (char c : text) {
    if (decoder.push(c, f)) frames.push_back(f);
  }
  return frames;
}

TEST(Slcan, EncodesStandardFramesAsLawicelLines) {
  EXPECT_EQ(line_of(encode(ValveCommandMessage{2, 15, 0x0102})), "t2204020F0201\r");
  EXPECT_EQ(line_of(encode(HeartbeatMessage{1, 5})), "t701105\r");
  CanFrame ext;
  ext.id = 0x1ABCDEF0;
  ext.extended = true;
  ext.dlc = 1;
  ext.data[0] = 0xAA;
  EXPECT_EQ(line_of(ext), "T1ABCDEF01AA\r");
  CanFrame rtr;
  rtr.id = 0x123;
  rtr.remote = true;
  rtr.dlc = 2;
  EXPECT_EQ(line_of(rtr), "r1232\r");
}

TEST(Slcan, RefusesToEncodeIntoTooSmallABufferOrAnInvalidFrame) {
  char small[5];
  EXPECT_EQ(slcan_encode(encode(LoadCellSampleMessage{}), small, sizeof small), 0u);
  CanFrame bad;
  bad.id = 0x800;  // over 11 bits
  char buffer[kSlcanMaxLine];
  EXPECT_EQ(slcan_encode(bad, buffer, sizeof buffer), 0u);
  bad.id = 1;
  bad.dlc = 9;
  EXPECT_EQ(slcan_encode(bad, buffer, sizeof buffer), 0u);
}

TEST(Slcan, RoundTripsEveryMessageOfTheProtocol) {
  const CanFrame frames[] = {encode(LoadCellSampleMessage{-123456, 65535, 4}), encode(ValveCommandMessage{1, 99, 7}),
                             encode(ValveFeedbackMessage{1, 0}), encode(IndicatorStatusMessage{50000, 1, 2, 3}),
                             encode(HeartbeatMessage{0x10, 0x7F})};
  std::string text;
  for (const CanFrame& f : frames) text += line_of(f);
  SlcanDecoder decoder;
  const auto decoded = feed(decoder, text);
  ASSERT_EQ(decoded.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(decoded[i], frames[i]) << i;
  EXPECT_EQ(decoder.errors(), 0u);
}

TEST(Slcan, AcceptsLowerCaseHexAndLineFeeds) {
  SlcanDecoder decoder;
  const auto frames = feed(decoder, "t1a02ff0e\n");
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].id, 0x1A0u);
  EXPECT_EQ(frames[0].data[0], 0xFF);
  EXPECT_EQ(frames[0].data[1], 0x0E);
}

TEST(Slcan, SkipsAdapterAnswersWithoutCountingErrors) {
  SlcanDecoder decoder;
  const auto frames = feed(decoder, "\r\aV1013\rz\rZ\rF00\rO\rt701105\r");
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].id, 0x701u);
  EXPECT_EQ(decoder.errors(), 0u);
}

TEST(Slcan, CountsMalformedFrameLinesAndRecoversAtTheNextLine) {
  SlcanDecoder decoder;
  const std::string bad[] = {
      "t1902AA\r",          // DLC 2 but one byte of data
      "t1902AABBCC\r",      // too much data
      "t19G1AA\r",          // not hex
      "t8001AA\r",          // 0x800: over 11 bits
      "t1909\r",            // DLC 9
      "t19\r",              // truncated identifier
      "T123\r",             // truncated extended identifier
      "t1908" + std::string(40, 'A') + "\r",  // far too long
  };
  std::string text;
  for (const auto& line : bad) text += line;
  text += "t1A020300\r";
  const auto frames = feed(decoder, text);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].id, 0x1A0u);
  EXPECT_EQ(decoder.errors(), 8u);
}

TEST(Slcan, AFrameSplitAcrossReadsIsReassembled) {
  SlcanDecoder decoder;
  EXPECT_TRUE(feed(decoder, "t2204010").empty());
  const auto frames = feed(decoder, "00500\r");
  ASSERT_EQ(frames.size(), 1u);
  ValveCommandMessage m;
  ASSERT_TRUE(decode(frames[0], m));
  EXPECT_EQ(m.command, 1);
  EXPECT_EQ(m.counter, 5);
}

}  // namespace
}  // namespace dynweigh::hal::can
