// The target's single-precision arithmetic (the M4F has no double) against a double reference on
// the host: the same means, the same printed decimals, the nearest float to what was typed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <string>

#include "dynweigh/firmware/compensated_sum.hpp"
#include "dynweigh/firmware/decimal_fraction.hpp"
#include "dynweigh/firmware/text_writer.hpp"

namespace dynweigh::firmware {
namespace {

std::string printed(float value, int decimals) {
  TextWriter writer;
  writer.write_decimal(value, decimals);
  char text[64] = {};
  writer.drain(text, sizeof text - 1);
  return text;
}

// What write_decimal printed when it scaled in double.
std::string printed_in_double(float value, int decimals) {
  double scale = 1.0;
  for (int i = 0; i < decimals; ++i) scale *= 10.0;
  const double scaled = double(value) * scale;
  const long long fixed = (long long)(scaled < 0 ? scaled - 0.5 : scaled + 0.5);
  const unsigned long long magnitude = (unsigned long long)(fixed < 0 ? -fixed : fixed);
  const unsigned long long units = (unsigned long long)scale;
  std::string text = (fixed < 0 ? "-" : "") + std::to_string(magnitude / units);
  std::string fraction = std::to_string(magnitude % units);
  fraction.insert(0, std::size_t(decimals) - (decimals ? fraction.size() : 0), '0');
  while (!fraction.empty() && fraction.back() == '0') fraction.pop_back();
  return fraction.empty() ? text : text + "." + fraction;
}

TEST(FloatArithmetic, CompensatedMeanOfAWindowOfWeightsEqualsTheDoubleMean) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> base(-20000.0f, 20000.0f), spread(0.0f, 2.0f);
  for (int window = 0; window < 2000; ++window) {
    const float level = window % 2 ? base(random) : base(random) * 1e-3f;
    CompensatedSum sum;
    double reference = 0.0;
    for (std::uint32_t n = 1; n <= 300; ++n) {
      const float value = level + spread(random);
      sum.add(value);
      reference += double(value);
      ASSERT_EQ(sum.mean(n), float(reference / double(n))) << "window " << window << " sample " << n;
    }
  }
  EXPECT_EQ(CompensatedSum().mean(0), 0.0f);
}

TEST(FloatArithmetic, WriteDecimalRoundsHalfAwayFromZeroAsInDouble) {
  EXPECT_EQ(printed(2.5f, 0), "3");
  EXPECT_EQ(printed(-2.5f, 0), "-3");
  EXPECT_EQ(printed(0.125f, 2), "0.13");
  EXPECT_EQ(printed(-0.0004f, 3), "0");
  EXPECT_EQ(printed(-0.0f, 1), "0");
  EXPECT_EQ(printed(1e-30f, 3), "0");
  EXPECT_EQ(printed(16777216.0f, 3), "16777216");
  std::mt19937 random(11);
  std::uniform_real_distribution<float> weight(-50000.0f, 50000.0f);
  std::uniform_int_distribution<int> decimals(0, 6), small(0, 40);
  for (int i = 0; i < 200000; ++i) {
    const float value = i % 2 ? weight(random) : std::ldexp(weight(random), -small(random));
    const int d = decimals(random);
    ASSERT_EQ(printed(value, d), printed_in_double(value, d)) << value << " to " << d << " decimals";
  }
}

TEST(FloatArithmetic, ATypedDecimalBecomesTheNearestFloat) {
  std::mt19937_64 random(3);
  for (int i = 0; i < 200000; ++i) {
    std::string whole = std::to_string(random() % 10000000000ull);
    whole.resize(1 + random() % whole.size());
    std::string fraction;
    for (int d = int(random() % 9); d > 0; --d) fraction += char('0' + random() % 10);
    const std::string text = fraction.empty() ? whole : whole + "." + fraction;
    const std::uint64_t numerator = std::stoull(whole + fraction);
    ASSERT_EQ(nearest_float(numerator, int(fraction.size()), false), std::strtof(text.c_str(), nullptr)) << text;
  }
  EXPECT_EQ(nearest_float(0, 3, false), 0.0f);
  EXPECT_EQ(nearest_float(16777217, 0, false), 16777216.0f);  // a tie: to even
  EXPECT_EQ(nearest_float(16777217, 0, true), 16777218.0f);   // just above the tie
  EXPECT_EQ(nearest_float(1, 18, false), 1e-18f);
}

}  // namespace
}  // namespace dynweigh::firmware
