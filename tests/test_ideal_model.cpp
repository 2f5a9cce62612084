// The ideal model of docs/physics.md against values worked by hand for the default scene
// (rho_b 1550 kg/m^3, D 60 mm, d 0.5 mm, h 1.2 m; docs/physics.md quotes W 2.41 kg/s, v0 0.55 m/s,
// t 0.44 s, 1.06 kg in flight, mdot v0 / g 135 g).
#include <gtest/gtest.h>

#include "dynweigh/model/beverloo.hpp"
#include "dynweigh/model/bore_area.hpp"
#include "dynweigh/model/final_weight_prediction.hpp"
#include "dynweigh/model/ideal_model.hpp"

namespace dynweigh::model {
namespace {

constexpr double g = 9.81;
const BeverlooMaterial<double> sand{0.58, 1.5, 0.0005, 1550.0};

TEST(IdealModel, BeverlooRateOfTheDefaultSceneMatchesTheReference) {
  // 0.58 * 1550 * sqrt(9.81) * 0.05925^2.5 = 2.4061 kg/s
  EXPECT_NEAR(beverloo_discharge_kg_s(sand, g, 0.060), 2.4061, 1e-3);
}

TEST(IdealModel, OutflowSpeedFallTimeAndMassInFlightMatchHandValues) {
  const double w = beverloo_discharge_kg_s(sand, g, 0.060);
  const double v0 = outflow_speed(w, bore_area_m2(0.060), 1550.0);
  EXPECT_NEAR(v0, 0.5490, 1e-3);                              // 2.4061 / (1550 * 2.8274e-3)
  EXPECT_NEAR(impact_speed(v0, g, 1.2), 4.8832, 1e-3);        // sqrt(0.5490^2 + 2 * 9.81 * 1.2)
  EXPECT_NEAR(fall_time(v0, g, 1.2), 0.4418, 1e-3);           // (4.8832 - 0.5490) / 9.81
  EXPECT_NEAR(mass_in_flight(w, v0, g, 1.2), 1.0630, 1e-3);   // 2.4061 * 0.4418
  EXPECT_NEAR(impulse_force(w, v0, g, 1.2), 11.749, 1e-2);    // 2.4061 * 4.8832
  EXPECT_NEAR(reading_excess_at_close_kg(w, v0, g), 0.13466, 1e-4);  // 2.4061 * 0.5490 / 9.81
}

TEST(IdealModel, MassFlowIsAlphaV0ARho) {
  EXPECT_DOUBLE_EQ(mass_flow(0.8, 0.5, 0.002, 1500.0), 0.8 * 0.5 * 0.002 * 1500.0);
}

TEST(IdealModel, RestDropMinusImpulseIsMinusMdotV0_TheCorrectedSign) {
  // Thesis eq. 1.14 claims +v0^2 A rho; eqs. 1.10 and 1.12 give -v0^2 A rho.
  const double v0 = 0.549, area = bore_area_m2(0.060), rho = 1550.0;
  const double mdot = mass_flow(1.0, v0, area, rho);
  const double rest_drop_force = mass_in_flight(mdot, v0, g, 1.2) * g;
  const double impulse = impulse_force(mdot, v0, g, 1.2);
  EXPECT_NEAR(rest_drop_force - impulse, -v0 * v0 * area * rho, 1e-9);
  EXPECT_LT(rest_drop_force - impulse, 0.0);
}

TEST(FinalWeightPrediction, IdealLimitIsReadingMinusMdotV0OverG) {
  CutoffGeometry<double> geometry;
  geometry.bore_area_m2 = bore_area_m2(0.060);
  geometry.pile_grows = false;
  const double mdot = 2.4061;
  const auto p = predict_final(geometry, 5.0, mdot);
  const double v0 = mdot / (1550.0 * geometry.bore_area_m2);
  EXPECT_NEAR(p.final_kg, 5.0 - mdot * v0 / g, 1e-12);
  EXPECT_NEAR(p.in_flight_kg, mass_in_flight(mdot, v0, g, 1.2), 1e-12);
}

TEST(FinalWeightPrediction, ValveLetThroughAddsItsSecondsOfFlow) {
  CutoffGeometry<double> geometry;
  geometry.bore_area_m2 = bore_area_m2(0.060);
  geometry.pile_grows = false;
  const auto without = predict_final(geometry, 5.0, 2.0);
  geometry.closing_flow_seconds = 0.05;
  const auto with = predict_final(geometry, 5.0, 2.0);
  EXPECT_NEAR(with.final_kg - without.final_kg, 0.1, 1e-12);
}

TEST(FinalWeightPrediction, RisingPileMeansLessReleasedThanLanding) {
  CutoffGeometry<double> geometry;
  geometry.bore_area_m2 = bore_area_m2(0.060);
  const auto p = predict_final(geometry, 5.0, 2.4);
  EXPECT_LT(p.release_kg_s, 2.4);
  EXPECT_GT(p.release_kg_s, 2.3);
  EXPECT_LT(p.fall_height_m, 1.2);
}

TEST(FinalWeightPrediction, FloatAndDoubleAgreeToAGram) {
  CutoffGeometry<double> gd;
  gd.bore_area_m2 = bore_area_m2(0.060);
  CutoffGeometry<float> gf;
  gf.bore_area_m2 = bore_area_m2(0.060f);
  const auto d = predict_final(gd, 9.5, 2.41);
  const auto f = predict_final(gf, 9.5f, 2.41f);
  EXPECT_NEAR(double(f.final_kg), d.final_kg, 1e-3);
}

}  // namespace
}  // namespace dynweigh::model
