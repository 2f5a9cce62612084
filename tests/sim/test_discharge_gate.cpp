// The discharge gate under the hopper: it strokes open over gate.stroke_s reporting moving then
// open, the hopper empties through it at gate.discharge_kg_s times its stroke, the scale reads the
// empty hopper again, a jammed gate holds, and mass is conserved with what left through it.
#include <gtest/gtest.h>

#include <cmath>

#include "dynweigh/sim/plant.hpp"
#include "dynweigh/sim/scene.hpp"
#include "dynweigh/sim/scene_file.hpp"

namespace dynweigh::sim {
namespace {

void fill(Plant& plant, double seconds) {
  plant.command_valve(ValveCommand::open);
  plant.advance(seconds);
  plant.command_valve(ValveCommand::closed);
  plant.advance(2.0);  // all landed
}

void expect_conserved(const Scene& scene, const PlantTruth& t) {
  const double in_kg = scene.silo.fill_kg + t.refilled_kg;
  ASSERT_NEAR(t.silo_kg + t.in_flight_kg + t.static_kg + t.discharged_kg, in_kg, 1e-10 * in_kg) << "t=" << t.time_s;
}

TEST(DischargeGate, OpensOverItsStrokeEmptiesTheHopperAndCloses) {
  Scene scene = default_scene();
  scene.gate.stroke_s = 0.4;
  scene.gate.discharge_kg_s = 3.0;
  Plant plant(scene, 2);
  fill(plant, 2.0);
  const double filled_kg = plant.truth().static_kg;
  ASSERT_GT(filled_kg, 3.0);
  EXPECT_EQ(plant.gate_feedback(), GateFeedback::closed);
  plant.command_gate(GateCommand::open);
  plant.advance(0.2);
  EXPECT_EQ(plant.gate_feedback(), GateFeedback::moving);
  // Half a stroke at a rising rate: 3 kg/s x 0.2 s x 0.25 (the mean of a ramp to half open).
  EXPECT_NEAR(plant.truth().discharged_kg, 3.0 * 0.2 * 0.25, 1e-6);
  plant.advance(0.21);
  EXPECT_EQ(plant.gate_feedback(), GateFeedback::open);
  while (plant.truth().static_kg > 0.0 && plant.truth().time_s < 60.0) {
    plant.advance(0.010);
    expect_conserved(scene, plant.truth());
  }
  EXPECT_EQ(plant.truth().static_kg, 0.0);
  EXPECT_NEAR(plant.truth().discharged_kg, filled_kg, 1e-9);
  plant.command_gate(GateCommand::closed);
  plant.advance(0.1);
  EXPECT_EQ(plant.gate_feedback(), GateFeedback::moving);
  plant.advance(10.0);
  EXPECT_EQ(plant.gate_feedback(), GateFeedback::closed);
  EXPECT_NEAR(plant.truth().force_n / scene.g, 0.0, 1e-4);  // the empty hopper, rung down
  expect_conserved(scene, plant.truth());
}

TEST(DischargeGate, AJammedGateHoldsWhateverItIsTold) {
  const Scene scene = default_scene();
  Plant plant(scene, 2);
  fill(plant, 1.0);
  plant.jam_gate(true);
  plant.command_gate(GateCommand::open);
  plant.advance(3.0);
  EXPECT_EQ(plant.gate_feedback(), GateFeedback::closed);
  EXPECT_EQ(plant.truth().discharged_kg, 0.0);
  plant.jam_gate(false);
  plant.advance(3.0);
  EXPECT_EQ(plant.gate_feedback(), GateFeedback::open);
  plant.jam_gate(true);  // stuck open
  plant.command_gate(GateCommand::closed);
  plant.advance(3.0);
  EXPECT_EQ(plant.gate_feedback(), GateFeedback::open);
}

TEST(DischargeGate, FillAndDischargeCyclesWithRefillConserveMass) {
  Scene scene = default_scene();
  scene.silo.refill_below_kg = 6.0;
  Plant plant(scene, 9);
  for (int cycle = 0; cycle < 12; ++cycle) {  // 12 x about 3.4 kg through an 18 kg silo
    fill(plant, 1.5);
    plant.command_gate(GateCommand::open);
    plant.advance(3.0);
    plant.command_gate(GateCommand::closed);
    plant.advance(1.0);
    expect_conserved(scene, plant.truth());
    EXPECT_GT(plant.truth().silo_kg, 0.0) << cycle;
  }
  EXPECT_GT(plant.truth().refilled_kg, 20.0);
  EXPECT_GT(plant.truth().discharged_kg, 38.0);
}

TEST(DischargeGate, SceneKeys) {
  const Scene scene = parse_scene_json(R"({"gate": {"discharge_kg_s": 6, "stroke_s": 1.5}})", "t");
  EXPECT_EQ(scene.gate.discharge_kg_s, 6.0);
  EXPECT_EQ(scene.gate.stroke_s, 1.5);
  EXPECT_THROW(parse_scene_json(R"({"gate": {"discharge_kg_s": 0}})", "t"), std::runtime_error);
}

}  // namespace
}  // namespace dynweigh::sim
