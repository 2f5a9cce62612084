// Calibration of lumped scenes from the detail models.
//
// The DEM test runs three 2D DEM doses of the default scene (open at 0, close at 0.8 s; 1200
// discs of 7.5 mm; about 6 s of CPU each, on two threads), calibrates the lumped scene from them
// and compares the two force signals on the scale. Tolerances, and why:
// - dead time within 25 ms: the DEM's first grains arrive 10-20 ms before a free fall from rest
//   would bring them (the compressed bed pushes them out as the gate uncovers the slot); the
//   lumped column starts each parcel at the mean outflow speed, so it cannot see that push.
//   25 ms is two and a half 10 ms samples of the firmware.
// - impulse and slope within 25 %: the DEM force of 2D discs bouncing on a rigid floor is noisy;
//   the standard error of the three-seed mean is about 10 % for both (measured: impulse 13.7 +-
//   1.6 N, slope 23.0 +- 2.3 N/s), so 25 % is two and a half standard errors.
// - final within 2 %: it is g times the released mass, which the calibration fits directly
//   (Beverloo C at the bore, start-up alpha); what is left is the close of the gate.
#include <gtest/gtest.h>

#include <cmath>

#include "dynweigh/granular/dem_calibration.hpp"
#include "dynweigh/granular/soc_fluid_calibration.hpp"
#include "dynweigh/sim/scene_file.hpp"

using namespace dynweigh;
using namespace dynweigh::granular;

TEST(DemSceneCalibration, CalibratedLumpedSceneReproducesTheDemDoseSignal) {
  const sim::Scene base = sim::default_scene();
  DemCalibrationOptions options;
  options.seeds = {1, 2, 3};
  options.sweep_orifices.clear();  // the scene's k; C fitted at the bore (the sweep is for the command)
  const std::vector<DemJobResult> results = run_dem_jobs(dem_calibration_jobs(base, options), 2);
  const DemCalibration calibration = calibrate_from_dem(base, results, options);
  const std::vector<ModelComparison> rows = compare_with_dem(base, calibration, results, options);
  ASSERT_EQ(rows.size(), 4u);
  const ModelComparison& lumped = rows[2];
  ASSERT_EQ(lumped.model, "lumped_calibrated");
  ASSERT_TRUE(lumped.features.valid);
  for (const ModelComparison& r : rows) {
    std::printf("%-20s cpu %9.4g s  dead %6.1f ms  impulse %5.1f %%  slope %5.1f %%  final %5.2f %%\n", r.model.c_str(),
                r.cpu_seconds_per_run, 1e3 * r.dead_time_error_s, 100 * r.impulse_error, 100 * r.slope_error,
                100 * r.final_error);
  }
  EXPECT_LT(lumped.dead_time_error_s, 0.025);
  EXPECT_LT(lumped.impulse_error, 0.25);
  EXPECT_LT(lumped.slope_error, 0.25);
  EXPECT_LT(lumped.final_error, 0.02);
  // The calibration is what brings the final weight in: the default scene's own parameters
  // release a different mass through the DEM's schedule.
  EXPECT_LT(lumped.final_error, rows[3].final_error);
  // At a tiny fraction of the cost.
  EXPECT_LT(lumped.cpu_seconds_per_run * 1000.0, rows[0].cpu_seconds_per_run);
  // The figures are the DEM's: rate within 15 % of the scene's Beverloo 2.41 kg/s (the slot has
  // the bore's area), a bulk density within 5 % of the scene's, and a sub-unity flow factor.
  EXPECT_NEAR(calibration.dem_rate_kg_s, 2.41, 0.15 * 2.41);
  EXPECT_NEAR(calibration.bed_bulk_density, base.silo.bulk_density, 0.05 * base.silo.bulk_density);
  EXPECT_GT(calibration.flow_factor.mean, 0.5);
  EXPECT_LT(calibration.flow_factor.mean, 1.0);
  // Mass: what was released and stayed in the container weighs on it at the end; a few 2D discs
  // (restitution 0.5 off a rigid floor) bounce over the 0.3 m walls: under 2 % of the mass.
  for (const DemJobResult& r : results) {
    EXPECT_NEAR(r.features.final_n, (r.run.released_total_kg - r.run.lost_kg) * base.g, 0.005 * r.features.final_n);
    EXPECT_LT(r.run.lost_kg, 0.02 * r.run.released_total_kg);
  }
}

TEST(SceneToJson, ACalibratedSceneFileReadsBackToTheSameScene) {
  sim::Scene scene = sim::default_scene();
  scene.name = "round-trip";
  scene.silo.flow_factor = 0.7871;
  scene.silo.beverloo_C = 1.0332;
  scene.impact.relaxation_s = 0.0043;
  const std::string text = sim::scene_to_json(scene, "{\"from\": \"test\"}");
  const sim::Scene back = sim::parse_scene_json(text, "round-trip");
  EXPECT_EQ(sim::describe_scene(back), sim::describe_scene(scene));
}

TEST(SceneToJson, FlowFactorOutsideZeroToOneIsRejected) {
  EXPECT_THROW(sim::parse_scene_json(R"({"silo": {"flow_factor": 0}})", "t"), std::runtime_error);
  EXPECT_THROW(sim::parse_scene_json(R"({"silo": {"flow_factor": 1.2}})", "t"), std::runtime_error);
  EXPECT_DOUBLE_EQ(sim::parse_scene_json(R"({"silo": {"flow_factor": 0.5}})", "t").silo.flow_factor, 0.5);
}

TEST(FluidCalibration, RoundBoreGivesThePoiseuilleMeanToMaxRatioOfOneHalf) {
  // Laminar flow in a round pipe: u = umax (1 - r^2 / R^2), mean / max = 1/2 exactly; the
  // staircase wall of the grid is what is left.
  const FluidSceneCalibration c = calibrate_from_fluid(sim::default_scene(), 257);
  EXPECT_NEAR(c.alpha, 0.5, 0.01);
  EXPECT_DOUBLE_EQ(c.scene.silo.flow_factor, c.alpha);
}

TEST(SocCalibration, HeapHeightGrowsAsTheSquareRootOfItsGrains) {
  // A 2D heap of constant slope holds N = h^2 / slope grains: h ~ N^(1/2).
  const SocSceneCalibration c = calibrate_from_soc(sim::default_scene(), 50000, 0, 1, 7);
  EXPECT_NEAR(c.height_exponent, 0.5, 0.05);
  EXPECT_GT(c.large_avalanches, 1);
  EXPECT_GT(c.scene.avalanche.critical_kg, 0.0);
  EXPECT_GT(c.repose_angle_deg, 20.0);
  EXPECT_LT(c.repose_angle_deg, 60.0);
}
