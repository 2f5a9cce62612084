#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "dynweigh/firmware/persistent_settings.hpp"

namespace dynweigh::firmware {
namespace {

PersistentSettings sample_settings() {
  PersistentSettings s;
  s.calibration = {-2147480000, 0.5f, 0.998f, true, true};
  s.parameters.set(ParameterId::fall_mm, 1500.0f);
  return s;
}

TEST(PersistentSettings, RoundTripsCalibrationAndParameters) {
  std::uint8_t record[kSettingsRecordSize];
  ASSERT_EQ(encode_settings(sample_settings(), record, sizeof record), kSettingsRecordSize);
  PersistentSettings decoded;
  ASSERT_TRUE(decode_settings(record, sizeof record, decoded));
  EXPECT_EQ(decoded.calibration.zero_counts, -2147480000);
  EXPECT_FLOAT_EQ(decoded.calibration.zero_fraction, 0.5f);
  EXPECT_FLOAT_EQ(decoded.calibration.counts_per_gram, 0.998f);
  EXPECT_TRUE(decoded.calibration.valid());
  EXPECT_FLOAT_EQ(decoded.parameters.get(ParameterId::fall_mm), 1500.0f);
}

TEST(PersistentSettings, EveryFlippedBitAndEveryTruncationIsRejected) {
  std::uint8_t record[kSettingsRecordSize];
  encode_settings(sample_settings(), record, sizeof record);
  PersistentSettings untouched;
  for (std::size_t byte = 0; byte < kSettingsRecordSize; ++byte) {
    for (int bit = 0; bit < 8; ++bit) {
      record[byte] ^= std::uint8_t(1u << bit);
      ASSERT_FALSE(decode_settings(record, sizeof record, untouched)) << byte << ":" << bit;
      record[byte] ^= std::uint8_t(1u << bit);
    }
    ASSERT_FALSE(decode_settings(record, byte, untouched));
  }
  EXPECT_FALSE(untouched.calibration.valid());
}

TEST(PersistentSettings, BlankStoreIsNotASettingsRecord) {
  std::uint8_t blank[kSettingsRecordSize];
  std::fill(std::begin(blank), std::end(blank), 0xFF);  // erased flash
  PersistentSettings s;
  EXPECT_FALSE(decode_settings(blank, sizeof blank, s));
}

TEST(Crc32, MatchesTheStandardCheckValue) {
  const char* check = "123456789";
  EXPECT_EQ(crc32(reinterpret_cast<const std::uint8_t*>(check), 9), 0xCBF43926u);
}

}  // namespace
}  // namespace dynweigh::firmware

namespace dynweigh::firmware {
namespace {

BaselineLearning learned_baselines() {
  BaselineLearning b;
  b.pac.spill = {180.0f, 12.0f, 40.0f, -3.0f, 2.0f, 7};
  b.pac.blind = {2400.0f, -90.0f, 1e4f, -500.0f, 300.0f, 3};
  b.flowpreact.lag_s = 0.21f;
  b.flowpreact.fills = 5;
  b.flowpreact.blind = {2300.0f, -80.0f, 2e4f, -100.0f, 200.0f, 2};
  return b;
}

TEST(PersistentSettings, RoundTripsWhatThePacAndFlowPreactBaselinesLearned) {
  PersistentSettings s = sample_settings();
  s.baselines = learned_baselines();
  std::uint8_t record[kSettingsRecordSize];
  ASSERT_EQ(encode_settings(s, record, sizeof record), kSettingsRecordSize);
  PersistentSettings decoded;
  ASSERT_TRUE(decode_settings(record, sizeof record, decoded));
  EXPECT_FLOAT_EQ(decoded.baselines.pac.spill.theta1, 180.0f);
  EXPECT_FLOAT_EQ(decoded.baselines.pac.spill.theta2, 12.0f);
  EXPECT_FLOAT_EQ(decoded.baselines.pac.spill.p12, -3.0f);
  EXPECT_EQ(decoded.baselines.pac.spill.fills, 7);
  EXPECT_FLOAT_EQ(decoded.baselines.pac.blind.theta2, -90.0f);
  EXPECT_FLOAT_EQ(decoded.baselines.flowpreact.lag_s, 0.21f);
  EXPECT_EQ(decoded.baselines.flowpreact.fills, 5);
  EXPECT_FLOAT_EQ(decoded.baselines.flowpreact.blind.theta1, 2300.0f);
}

// A law no learning produces (its covariance not positive definite, a value not finite, a lag out of
// reason) is dropped on reading, the rest of the record kept: the strategy starts from its prior.
TEST(PersistentSettings, ALearnedBaselineLawThatIsNoLawIsDropped) {
  PersistentSettings s = sample_settings();
  s.baselines = learned_baselines();
  s.baselines.pac.spill.p12 = 100.0f;  // p12^2 > p11 p22
  s.baselines.pac.blind.theta1 = std::numeric_limits<float>::infinity();
  s.baselines.flowpreact.lag_s = 1e9f;
  std::uint8_t record[kSettingsRecordSize];
  ASSERT_EQ(encode_settings(s, record, sizeof record), kSettingsRecordSize);
  PersistentSettings decoded;
  ASSERT_TRUE(decode_settings(record, sizeof record, decoded));
  EXPECT_EQ(decoded.baselines.pac.spill.fills, 0);
  EXPECT_EQ(decoded.baselines.pac.blind.fills, 0);
  EXPECT_EQ(decoded.baselines.flowpreact.fills, 0);
  EXPECT_EQ(decoded.baselines.flowpreact.blind.fills, 2);  // intact: kept
  EXPECT_FLOAT_EQ(decoded.parameters.get(ParameterId::fall_mm), 1500.0f);
}

}  // namespace
}  // namespace dynweigh::firmware
