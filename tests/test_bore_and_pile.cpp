#include <gtest/gtest.h>

#include <cmath>

#include "dynweigh/model/bore_area.hpp"
#include "dynweigh/model/gate_flow_shape.hpp"
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

// The integral along the stroke is taken once; the dead time and the stroke time only scale it.
// Against a fine midpoint rule: dead time at the starting stroke's flow, then the flow along a
// linear close, in seconds of full flow, from the open gate and from half stroke.
TEST(ValveLetThrough, TheOnceTakenIntegralMatchesAFineIntegrationAtAnyTiming) {
  const BeverlooMaterial<double> gravel{0.58, 1.5, 0.004, 1500.0};
  const double g = 9.81, bore_m = 0.06;
  const double full = discharge_at_stroke_kg_s(gravel, g, bore_m, 1.0);
  for (const double from : {1.0, 0.5}) {
    const ClosingFlowIntegral<double> integral(gravel, g, bore_m, from);
    double along = 0.0;  // integral of the flow's share over the stroke from closed to `from`
    constexpr int kSteps = 20000;
    for (int i = 0; i < kSteps; ++i) {
      along += discharge_at_stroke_kg_s(gravel, g, bore_m, from * (i + 0.5) / kSteps) / full * from / kSteps;
    }
    const double at_start = discharge_at_stroke_kg_s(gravel, g, bore_m, from) / full;
    for (const double dead_s : {0.0, 0.02, 0.08}) {
      for (const double stroke_s : {0.04, 0.3}) {
        EXPECT_NEAR(integral.seconds(dead_s, stroke_s), dead_s * at_start + stroke_s * along, 1e-5)
            << "from " << from << " dead " << dead_s << " stroke " << stroke_s;
        EXPECT_EQ(integral.seconds(dead_s, stroke_s), closing_flow_seconds(gravel, g, bore_m, dead_s, stroke_s, from));
      }
    }
  }
}

// Coarse grains (6 mm of arching) through a 60 mm bore: no flow until the slit is wider than the
// arches, then a flow that grows much faster than the stroke. The table holds Beverloo's flow at its
// knots and its integral along the stroke to a fine midpoint rule's; the inverse finds the stroke.
TEST(GateFlowShape, IsBeverloosFlowAndItsIntegralAlongTheStroke) {
  const BeverlooMaterial<double> gravel{0.58, 1.5, 0.004, 1500.0};
  const double g = 9.81, bore_m = 0.06;
  const GateFlowShape<double> shape = gate_flow_shape(gravel, g, bore_m);
  const double full = discharge_at_stroke_kg_s(gravel, g, bore_m, 1.0);
  const auto share = [&](double stroke) { return discharge_at_stroke_kg_s(gravel, g, bore_m, stroke) / full; };
  EXPECT_NEAR(shape.flow_at(1.0), 1.0, 1e-12);
  EXPECT_NEAR(shape.flow_at(0.5), share(0.5), 1e-12);
  EXPECT_DOUBLE_EQ(shape.flow_at(0.0), 0.0);
  for (double stroke : {0.25, 0.5, 0.8, 1.0}) {
    constexpr int kSteps = 20000;
    double integral = 0.0;
    for (int i = 0; i < kSteps; ++i) integral += share((i + 0.5) * stroke / kSteps) * stroke / kSteps;
    EXPECT_NEAR(shape.integral_to(stroke), integral, 2e-3) << "stroke " << stroke;
    EXPECT_NEAR(shape.stroke_for_integral(shape.integral_to(stroke)), stroke, 1e-9) << "stroke " << stroke;
  }
  // Less than a flow in proportion to the stroke gives (its square over two), and far less over a
  // short stroke: what a short pulse delivers.
  EXPECT_LT(shape.integral_to(1.0), 0.45);
  EXPECT_LT(shape.integral_to(0.25), 0.5 * (0.25 * 0.25 / 2.0));
}

// A bore the grains arch over lets nothing through at any stroke: the shape falls back to a flow in
// proportion to the stroke, whose integral is the stroke's square over two.
TEST(GateFlowShape, ABoreThatArchesOverIsTakenAsProportional) {
  const BeverlooMaterial<double> gravel{0.58, 1.5, 0.004, 1500.0};
  const GateFlowShape<double> shape = gate_flow_shape(gravel, 9.81, 0.005);
  for (double stroke : {0.0, 0.25, 0.5, 1.0}) {
    EXPECT_NEAR(shape.flow_at(stroke), stroke, 1e-12);
    EXPECT_NEAR(shape.integral_to(stroke), stroke * stroke / 2.0, 1e-12);
  }
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
