// The silo refilled from upstream: the level switch and feeder of silo.refill_below_kg /
// silo.refill_rate_kg_s, and the plant commands. Mass is conserved with what came in:
// silo + in flight + on the scale = fill + refilled, at every step.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dynweigh/sim/plant.hpp"
#include "dynweigh/sim/scene.hpp"
#include "dynweigh/sim/scene_file.hpp"

namespace dynweigh::sim {
namespace {

Scene refilled_scene() {
  Scene scene = default_scene();
  scene.silo.refill_below_kg = 6.0;
  scene.silo.refill_rate_kg_s = 2.0;  // slower than the outflow: the level still falls while open
  return scene;
}

void expect_conserved(const Scene& scene, const PlantTruth& t) {
  const double in_kg = scene.silo.fill_kg + t.refilled_kg;
  ASSERT_NEAR(t.silo_kg + t.in_flight_kg + t.static_kg, in_kg, 1e-10 * in_kg) << "t=" << t.time_s;
}

TEST(SiloRefill, LongOpeningNeverRunsDryAndConservesMass) {
  const Scene scene = refilled_scene();
  Plant plant(scene, 5);
  double lowest_kg = scene.silo.fill_kg;
  plant.command_valve(ValveCommand::open);
  for (int jiffy = 0; jiffy < 2000; ++jiffy) {  // 20 s open: 48 kg through an 18 kg silo
    plant.advance(0.010);
    expect_conserved(scene, plant.truth());
    lowest_kg = std::min(lowest_kg, plant.truth().silo_kg);
  }
  const PlantTruth& t = plant.truth();
  EXPECT_GT(t.released_kg, 40.0);
  EXPECT_GT(t.refilled_kg, 20.0);
  EXPECT_GT(lowest_kg, 0.0);
  EXPECT_LT(lowest_kg, scene.silo.refill_below_kg);
}

TEST(SiloRefill, TheFeederStopsAtTheFillLevel) {
  const Scene scene = refilled_scene();
  Plant plant(scene, 5);
  plant.command_valve(ValveCommand::open);
  while (plant.truth().silo_kg >= scene.silo.refill_below_kg) plant.advance(0.010);
  plant.command_valve(ValveCommand::closed);
  plant.advance(30.0);
  EXPECT_FALSE(plant.truth().refilling);
  EXPECT_NEAR(plant.truth().silo_kg, scene.silo.fill_kg, 1e-9);
  expect_conserved(scene, plant.truth());
}

TEST(SiloRefill, WithoutARefillLevelTheSiloRunsDryAsBefore) {
  const Scene scene = default_scene();
  Plant plant(scene, 5);
  plant.command_valve(ValveCommand::open);
  plant.advance(12.0);
  EXPECT_EQ(plant.truth().silo_kg, 0.0);
  EXPECT_EQ(plant.truth().refilled_kg, 0.0);
  EXPECT_NEAR(plant.truth().released_kg, scene.silo.fill_kg, 1e-9);
}

TEST(SiloRefill, PlantCommandsPourInAtOnceOrStartTheFeeder) {
  Scene scene = default_scene();
  scene.silo.refill_rate_kg_s = 2.0;
  Plant plant(scene, 5);
  plant.command_valve(ValveCommand::open);
  plant.advance(12.0);  // dry
  plant.command_valve(ValveCommand::closed);
  plant.advance(1.0);
  plant.add_to_silo(3.0);
  EXPECT_NEAR(plant.truth().silo_kg, 3.0, 1e-12);
  plant.start_refill();
  plant.advance(1.0);
  EXPECT_NEAR(plant.truth().silo_kg, 5.0, 1e-9);  // 2 kg/s for 1 s
  plant.advance(10.0);
  EXPECT_NEAR(plant.truth().silo_kg, scene.silo.fill_kg, 1e-9);
  EXPECT_FALSE(plant.truth().refilling);
  expect_conserved(scene, plant.truth());
}

TEST(SiloRefill, SceneFileRefusesALevelAboveTheFill) {
  EXPECT_THROW(parse_scene_json(R"({"silo": {"fill_kg": 10, "refill_below_kg": 12}})", "t"), std::runtime_error);
  EXPECT_THROW(parse_scene_json(R"({"silo": {"refill_rate_kg_s": 0}})", "t"), std::runtime_error);
  const Scene scene = parse_scene_json(R"({"silo": {"refill_below_kg": 5, "refill_rate_kg_s": 3}})", "t");
  EXPECT_EQ(scene.silo.refill_below_kg, 5.0);
  EXPECT_EQ(scene.silo.refill_rate_kg_s, 3.0);
}

}  // namespace
}  // namespace dynweigh::sim
