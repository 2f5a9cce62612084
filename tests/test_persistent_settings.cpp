#include <gtest/gtest.h>

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
