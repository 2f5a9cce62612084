// The backbone's plant invariants (docs/physics.md) and the sign of the corrected ideal model.
#include <gtest/gtest.h>

#include <cmath>

#include "dynweigh/model/beverloo.hpp"
#include "dynweigh/model/bore_area.hpp"
#include "dynweigh/model/ideal_model.hpp"
#include "dynweigh/sim/plant.hpp"

namespace dynweigh::sim {
namespace {

TEST(PlantBackbone, ReleasedEqualsOnScalePlusInFlightAtEveryStep) {
  Plant plant(default_scene(), 7);
  plant.command_valve(ValveCommand::open);
  for (int jiffy = 0; jiffy < 1000; ++jiffy) {
    if (jiffy == 400) plant.command_valve(ValveCommand::half);
    if (jiffy == 500) plant.command_valve(ValveCommand::closed);
    for (int i = 0; i < 10; ++i) {
      plant.advance(0.001);
      const PlantTruth& t = plant.truth();
      ASSERT_NEAR(t.released_kg, t.static_kg + t.in_flight_kg, 1e-12) << "t=" << t.time_s;
      ASSERT_GE(t.in_flight_kg, -1e-15);
    }
  }
}

TEST(PlantBackbone, SettledReadingIsGTimesReleasedMassTo01g) {
  Plant plant(default_scene(), 3);
  plant.command_valve(ValveCommand::open);
  plant.advance(3.0);
  plant.command_valve(ValveCommand::closed);
  plant.advance(25.0);  // the loaded platform rings down (zeta about 0.03)
  const PlantTruth& t = plant.truth();
  EXPECT_GT(t.released_kg, 5.0);
  EXPECT_NEAR(t.force_n / plant.scene().g, t.released_kg, 1e-4);
  EXPECT_DOUBLE_EQ(t.in_flight_kg, 0.0);
}

TEST(PlantBackbone, ReadingAtCloseExceedsFinalByMdotV0OverG_IdealLimit) {
  const Scene scene = ideal_scene();
  Plant plant(scene, 1);
  plant.command_valve(ValveCommand::open);
  plant.advance(3.0);  // steady stream, constant h
  const double reading_at_close = plant.truth().force_n / scene.g;
  plant.command_valve(ValveCommand::closed);
  plant.advance(2.0);
  const double final_static = plant.truth().force_n / scene.g;

  const model::BeverlooMaterial<double> sand{scene.silo.beverloo_C, scene.silo.beverloo_k, scene.silo.grain_d_m,
                                             scene.silo.bulk_density};
  const double mdot = model::beverloo_discharge_kg_s(sand, scene.g, scene.silo.bore_m);
  const double v0 = model::outflow_speed(mdot, model::bore_area_m2(scene.silo.bore_m), scene.silo.bulk_density);
  const double expected = model::reading_excess_at_close_kg(mdot, v0, scene.g);  // about 135 g
  EXPECT_NEAR(expected, 0.1347, 1e-3);
  EXPECT_NEAR(reading_at_close - final_static, expected, 0.005 * expected);
  EXPECT_GT(reading_at_close, final_static);  // the thesis' sign would put it below
}

TEST(PlantBackbone, SameSeedSameRunDifferentSeedDifferentNoise) {
  auto run = [](std::uint64_t seed) {
    Plant plant(default_scene(), seed);
    plant.command_valve(ValveCommand::open);
    double checksum = 0.0;
    for (int j = 0; j < 300; ++j) {
      plant.advance(0.01);
      checksum = checksum * 1.0000001 + double(plant.sample().raw_counts);
    }
    return checksum;
  };
  EXPECT_EQ(run(11), run(11));
  EXPECT_NE(run(11), run(12));
}

}  // namespace
}  // namespace dynweigh::sim
