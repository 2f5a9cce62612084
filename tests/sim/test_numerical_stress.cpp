// Numerical stress: no parameter a scene allows may make a run blow up. Across platform
// frequency, damping, flow rate, fall height, a zero outflow speed, a silo running empty and a
// day-long run: no NaN, no Inf, no negative mass, and the invariants hold.
#include <gtest/gtest.h>

#include <cmath>

#include "dynweigh/sim/falling_column.hpp"
#include "plant_runs.hpp"

namespace dynweigh::sim {
namespace {

// Runs open for `open_s`, then closed until everything settled; checks the invariants each jiffy.
void expect_sound_run(const Scene& scene, double open_s, double settle_s, const std::string& label) {
  Plant plant(scene, 11);
  plant.command_valve(ValveCommand::open);
  const int jiffies = int(std::lround((open_s + settle_s) / kJiffyS));
  for (int j = 0; j < jiffies; ++j) {
    if (j == int(std::lround(open_s / kJiffyS))) plant.command_valve(ValveCommand::closed);
    plant.advance(kJiffyS);
    const PlantTruth& t = plant.truth();
    const LoadCellSample sample = plant.sample();
    ASSERT_TRUE(std::isfinite(t.force_n) && std::isfinite(t.impact_force_n) && std::isfinite(t.fall_height_m))
        << label << " t=" << t.time_s;
    ASSERT_GE(t.static_kg, 0.0) << label;
    ASSERT_GE(t.in_flight_kg, 0.0) << label;
    ASSERT_GE(t.silo_kg, 0.0) << label;
    ASSERT_NEAR(t.released_kg, t.static_kg + t.in_flight_kg, 1e-12 * (1.0 + t.released_kg)) << label;
    ASSERT_NEAR(t.released_kg + t.silo_kg, scene.silo.fill_kg, 1e-12 * (1.0 + scene.silo.fill_kg)) << label;
    ASSERT_GT(t.fall_height_m, 0.0) << label;
    (void)sample;
  }
  const PlantTruth& t = plant.truth();
  EXPECT_EQ(t.in_flight_kg, 0.0) << label;
  const double expected_kg = scene.hourglass.enabled ? 0.0 : t.released_kg;
  EXPECT_NEAR(t.force_n / scene.g, expected_kg, 1e-4) << label;
}

TEST(NumericalStress, PlatformFrom1To200HzAndDampingFrom0001To1) {
  for (double hz : {1.0, 12.0, 200.0}) {
    for (double zeta : {0.001, 0.05, 1.0}) {
      Scene scene = default_scene();
      scene.platform.natural_hz = hz;
      scene.platform.damping_ratio = zeta;
      // The oscillation decays at c / (2 m): give it time to fall by 1e-5 (below 0.1 g) with the
      // 2.4 kg dose on the platform. The 1 Hz, zeta 0.001 platform needs most of an hour: it runs
      // at the coarsest step a scene allows, which the exact platform stepping permits.
      const double loaded_kg = scene.platform.container_kg + 2.5;
      const double decay_per_s = zeta * 2.0 * M_PI * hz * scene.platform.container_kg / loaded_kg;
      const double settle_s = std::max(20.0, std::log(1e5) / decay_per_s);
      if (settle_s > 100.0) scene.internal_step_s = 0.010;
      expect_sound_run(scene, 1.0, settle_s, std::to_string(hz) + " Hz zeta " + std::to_string(zeta));
    }
  }
}

TEST(NumericalStress, FlowFrom1gPerSecondTo20kgPerSecond) {
  // Beverloo with the default sand: D = 3.5 mm gives about 1 g/s, D = 140 mm about 20 kg/s.
  for (double bore_m : {0.0035, 0.060, 0.140}) {
    Scene scene = default_scene();
    scene.silo.bore_m = bore_m;
    scene.silo.fill_kg = 30.0;
    scene.load_cell.capacity_kg = 100.0;
    const double rate = Plant(scene, 1).full_open_rate_kg_s();
    EXPECT_TRUE(rate > 0.0005 && rate < 25.0) << rate;
    expect_sound_run(scene, 1.0, 40.0, "bore " + std::to_string(bore_m));
  }
}

TEST(NumericalStress, FallHeightFrom1mmTo5m) {
  for (double h : {0.001, 0.05, 1.2, 5.0}) {
    for (bool pile : {false, true}) {
      Scene scene = default_scene();
      scene.column.fall_height_m = h;
      scene.column.pile_grows = pile;
      expect_sound_run(scene, 2.0, 40.0, "h " + std::to_string(h) + (pile ? " pile" : " fixed"));
    }
  }
}

TEST(NumericalStress, ParcelsLeavingAtZeroSpeedLandAfterTheFreeFallTime) {
  const double g = 9.81, h = 1.2, dt = 1e-3;
  FallingColumn column(g, 4096);
  column.release(0.0, 1.0, 0.0);
  double landed_at = -1.0;
  for (int i = 0; i < 1000 && landed_at < 0.0; ++i) {
    const auto landing = column.land(i * dt, (i + 1) * dt, h);
    ASSERT_TRUE(std::isfinite(landing.momentum_n_s));
    if (landing.mass_kg > 0.0) {
      landed_at = (i + 1) * dt;
      EXPECT_NEAR(landing.momentum_n_s, std::sqrt(2.0 * g * h), 1e-9);  // 1 kg at sqrt(2 g h)
    }
  }
  EXPECT_NEAR(landed_at, std::sqrt(2.0 * h / g), dt);
}

TEST(NumericalStress, SiloRunsEmptyMidCycle) {
  for (const char* name : {"default", "hourglass", "fine-powder"}) {
    Scene scene = testing::shipped_scene(name);
    scene.silo.fill_kg = 1.5;
    expect_sound_run(scene, 3.0, 40.0, std::string("empty ") + name);
  }
}

TEST(NumericalStress, ExtremeScenesEveryComponentOn) {
  Scene scene = testing::shipped_scene("hourglass");
  scene.creep.enabled = true;
  scene.platform.natural_hz = 200.0;
  scene.column.fall_height_m = 5.0;
  scene.avalanche.critical_kg = 1e-4;  // many overlapping avalanches
  expect_sound_run(scene, 3.0, 30.0, "everything");
}

// A day of simulated time: an hourly dose until the silo is empty, then idle with creep on.
TEST(NumericalStress, TwentyFourHourRunStaysFiniteAndConservesMass) {
  Scene scene = default_scene();
  scene.internal_step_s = 0.010;  // the coarsest step a scene allows: keeps the day fast
  scene.creep.enabled = true;
  Plant plant(scene, 3);
  const int jiffies_per_hour = 360000;
  for (int hour = 0; hour < 24; ++hour) {
    for (int j = 0; j < jiffies_per_hour; ++j) {
      if (j == 0) plant.command_valve(ValveCommand::open);
      if (j == 200) plant.command_valve(ValveCommand::closed);
      plant.advance(kJiffyS);
      const LoadCellSample sample = plant.sample();
      const PlantTruth& t = plant.truth();
      if (!std::isfinite(t.force_n) || t.in_flight_kg < 0.0 ||
          std::abs(t.released_kg - t.static_kg - t.in_flight_kg) > 1e-9) {
        FAIL() << "hour " << hour << " jiffy " << j << " force " << t.force_n;
      }
      (void)sample;
    }
  }
  const PlantTruth& t = plant.truth();
  EXPECT_NEAR(t.time_s, 86400.0, 1e-6);
  EXPECT_NEAR(t.released_kg, scene.silo.fill_kg, 1e-9);  // 18 kg: empty after eight 2 s doses
  EXPECT_NEAR(t.force_n / scene.g, t.released_kg, 1e-4);
}

}  // namespace
}  // namespace dynweigh::sim
