// OIML R61 classes against values worked by hand from the table in docs/benchmarks.md.
#include <gtest/gtest.h>

#include "dynweigh/model/oiml_r61_class.hpp"

namespace dynweigh::model {
namespace {

TEST(OimlR61, X1LimitsAtTheBandEdges) {
  EXPECT_NEAR(oiml_x1_limits(50).initial_verification_g, 3.15, 1e-9);   // 6.3 % of 50 g
  EXPECT_NEAR(oiml_x1_limits(80).initial_verification_g, 3.15, 1e-9);
  EXPECT_NEAR(oiml_x1_limits(200).initial_verification_g, 6.3, 1e-9);   // 3.15 % of 200 g
  EXPECT_NEAR(oiml_x1_limits(500).initial_verification_g, 10.5, 1e-9);  // 2.1 % of 500 g
  EXPECT_NEAR(oiml_x1_limits(2000).initial_verification_g, 21.0, 1e-9); // 1.05 % of 2 kg
  EXPECT_NEAR(oiml_x1_limits(10000).in_service_g, 150.0, 1e-9);         // 1.5 % of 10 kg
  EXPECT_NEAR(oiml_x1_limits(12000).initial_verification_g, 105.0, 1e-9);
  EXPECT_NEAR(oiml_x1_limits(20000).initial_verification_g, 140.0, 1e-9);  // 0.7 % of 20 kg
}

TEST(OimlR61, TenKilogramsInX02IsTwentyOneGramsAndSevenAndAHalfBias) {
  // docs/benchmarks.md: every fill within 21 g of the mean, the mean within 7.5 g of 10 kg.
  EXPECT_EQ(best_oiml_class(10000, 21.0, 7.5), 0.2);
  EXPECT_EQ(best_oiml_class(10000, 21.1, 7.5), 0.5);  // one fill too far: next class
  EXPECT_EQ(best_oiml_class(10000, 21.0, 7.6), 0.5);  // preset error too large
  EXPECT_EQ(best_oiml_class(10000, 10.5, 3.75), 0.1);
}

TEST(OimlR61, NoClassForAWildSeries) {
  EXPECT_EQ(best_oiml_class(500, 2000.0, 0.0), 0.0);
  EXPECT_EQ(best_oiml_class(2000, 5.0, 1000.0), 0.0);
}

TEST(OimlR61, OneFillsClassIsTheSmallestWhoseInitialVerificationLimitHoldsItsDeviation) {
  // 2 kg: X(1) holds 21 g; X(0.5) 10.5 g; X(5) 105 g.
  EXPECT_EQ(oiml_class_of_deviation(2000, 21.0), 1.0);
  EXPECT_EQ(oiml_class_of_deviation(2000, -21.0), 1.0);  // short or over alike
  EXPECT_EQ(oiml_class_of_deviation(2000, 21.1), 2.0);
  EXPECT_EQ(oiml_class_of_deviation(2000, 10.5), 0.5);
  EXPECT_EQ(oiml_class_of_deviation(2000, 0.0), 0.1);
  EXPECT_EQ(oiml_class_of_deviation(500, 105.0), 10.0);
  EXPECT_EQ(oiml_class_of_deviation(500, 1051.0), 0.0);  // beyond X(100)
}

}  // namespace
}  // namespace dynweigh::model
