#include <gtest/gtest.h>

#include <cmath>

#include "dynweigh/model/bore_area.hpp"
#include "dynweigh/model/pile_geometry.hpp"
#include "dynweigh/model/valve_let_through.hpp"

namespace dynweigh::model {
namespace {

TEST(BoreArea, SegmentOfACircleAtQuarterHalfAndFullStroke) {
  EXPECT_DOUBLE_EQ(open_area_fraction(0.0), 0.0);
  EXPECT_NEAR(open_area_fraction(0.5), 0.5, 1e-12);
  EXPECT_NEAR(open_area_fraction(1.0), 1.0, 1e-12);
  // Segment of height R/2 in a unit-radius circle: (2pi/3 - sqrt(3)/2) / (2 pi) = 0.19550
  EXPECT_NEAR(open_area_fraction(0.25), 0.19550, 1e-4);
}

TEST(ValveLetThrough, InstantValveLetsNothingThroughAndDeadTimeCountsFully) {
  const BeverlooMaterial<double> sand{};
  EXPECT_NEAR(closing_flow_seconds(sand, 9.81, 0.06, 0.0, 0.0), 0.0, 1e-12);
  EXPECT_NEAR(closing_flow_seconds(sand, 9.81, 0.06, 0.03, 0.0), 0.03, 1e-12);
  const double stroking = closing_flow_seconds(sand, 9.81, 0.06, 0.0, 0.08);
  EXPECT_GT(stroking, 0.0);
  EXPECT_LT(stroking, 0.04);  // Beverloo falls faster than the area: less than half the stroke
}

TEST(PileGeometry, ConeThenCylinder) {
  PileGeometry<double> pile{0.3, 32.0 * M_PI / 180.0, 1550.0};
  const double radius = 0.15, slope = std::tan(pile.repose_angle_rad);
  const double cone_kg = M_PI * radius * radius * radius * slope / 3.0 * 1550.0;
  EXPECT_NEAR(pile_top_height_m(pile, cone_kg), radius * slope, 1e-9);
  const double extra = 1550.0 * M_PI * radius * radius * 0.05;  // 5 cm of cylinder
  EXPECT_NEAR(pile_top_height_m(pile, cone_kg + extra), radius * slope + 0.05, 1e-9);
  EXPECT_NEAR(pile_rise_m_per_kg(pile, cone_kg + extra), 1.0 / (1550.0 * M_PI * radius * radius), 1e-12);
  EXPECT_DOUBLE_EQ(fall_height_to_pile_m(pile, 1.2, 0.0), 1.2);
}

}  // namespace
}  // namespace dynweigh::model
