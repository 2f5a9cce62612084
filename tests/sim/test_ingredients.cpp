// Ingredients: up to eight silos, each with its own material, valve and height, into the one
// hopper on the one platform. Each stream keeps its own mass (what leaves its silo is in flight or
// in the hopper), an idle ingredient changes nothing for the others, and a scene lists them in
// `ingredients` (docs/scenes.md).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "dynweigh/sim/plant.hpp"
#include "dynweigh/sim/scene.hpp"
#include "dynweigh/sim/scene_file.hpp"
#include "plant_runs.hpp"

namespace dynweigh::sim {
namespace {

double fill_of(const Scene& scene, std::size_t ingredient) {
  return ingredient == 0 ? scene.silo.fill_kg : scene.ingredients[ingredient].silo.fill_kg;
}

void expect_each_stream_conserved(const Scene& scene, const Plant& plant) {
  const PlantTruth& t = plant.truth();
  double released = 0.0, in_flight = 0.0, silo = 0.0;
  for (std::size_t i = 0; i < plant.ingredient_count(); ++i) {
    const IngredientTruth& own = t.ingredients[i];
    const double fill = fill_of(scene, i);
    ASSERT_NEAR(own.released_kg + own.silo_kg, fill, 1e-12 * (1.0 + fill)) << "ingredient " << i << " t=" << t.time_s;
    ASSERT_GE(own.in_flight_kg, 0.0);
    released += own.released_kg;
    in_flight += own.in_flight_kg;
    silo += own.silo_kg;
  }
  ASSERT_NEAR(t.released_kg, released, 1e-12 * (1.0 + released));
  ASSERT_NEAR(t.in_flight_kg, in_flight, 1e-12 * (1.0 + in_flight));
  ASSERT_NEAR(t.silo_kg, silo, 1e-12 * (1.0 + silo));
  ASSERT_NEAR(t.released_kg, t.static_kg + t.in_flight_kg, 1e-12 * (1.0 + t.released_kg)) << "t=" << t.time_s;
}

// Runs `seconds` with the given ingredients open, then closes them and lets the streams land.
std::array<double, kMaxIngredients> open_then_settle(const Scene& scene, Plant& plant,
                                                      std::initializer_list<std::size_t> open, double seconds) {
  std::array<double, kMaxIngredients> before{};
  for (std::size_t i = 0; i < plant.ingredient_count(); ++i) before[i] = plant.truth().ingredients[i].released_kg;
  for (const std::size_t i : open) EXPECT_TRUE(plant.command_ingredient_valve(i, ValveCommand::open));
  for (int jiffy = 0; jiffy < int(std::lround(seconds / 0.010)); ++jiffy) {
    plant.advance(0.010);
    expect_each_stream_conserved(scene, plant);
  }
  for (const std::size_t i : open) plant.command_ingredient_valve(i, ValveCommand::closed);
  for (int jiffy = 0; jiffy < 200; ++jiffy) {
    plant.advance(0.010);
    expect_each_stream_conserved(scene, plant);
  }
  EXPECT_EQ(plant.truth().in_flight_kg, 0.0);
  std::array<double, kMaxIngredients> delivered{};
  for (std::size_t i = 0; i < plant.ingredient_count(); ++i) {
    delivered[i] = plant.truth().ingredients[i].released_kg - before[i];
  }
  return delivered;
}

TEST(Ingredients, TheBatchingSceneHasThreeMaterialsOfDifferentFlowAndDensity) {
  const Scene scene = testing::shipped_scene("batching");
  ASSERT_EQ(scene.ingredients.size(), 3u);
  Plant plant(scene, 1);
  EXPECT_EQ(plant.ingredient_count(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = i + 1; j < 3; ++j) {
      EXPECT_NE(scene.ingredients[i].material, scene.ingredients[j].material);
      EXPECT_GT(std::abs(scene.ingredients[i].silo.bulk_density - scene.ingredients[j].silo.bulk_density), 100.0);
    }
  }
  // Ingredient 0 is the scene's own silo.
  EXPECT_EQ(scene.ingredients[0].silo.bulk_density, scene.silo.bulk_density);
  EXPECT_EQ(scene.ingredients[0].fall_height_m, scene.column.fall_height_m);
}

TEST(Ingredients, EachStreamConservesItsMassOpenedInTurnAndTogether) {
  const Scene scene = testing::shipped_scene("batching");
  Plant plant(scene, 11);
  std::array<double, 3> rate_kg_s{};
  for (std::size_t i = 0; i < 3; ++i) {
    const double static_before = plant.truth().static_kg;
    const auto delivered = open_then_settle(scene, plant, {i}, 1.5);
    for (std::size_t j = 0; j < 3; ++j) {
      if (j == i) {
        EXPECT_GT(delivered[j], 0.5) << "ingredient " << i;
      } else {
        EXPECT_EQ(delivered[j], 0.0) << "ingredient " << j << " moved while " << i << " was open";
      }
    }
    // What left its silo is in the hopper, and the scale says so.
    EXPECT_NEAR(plant.truth().static_kg - static_before, delivered[i], 1e-12 * (1.0 + delivered[i]));
    rate_kg_s[i] = delivered[i] / 1.5;
  }
  // Clearly different flows: sand > barley > flour.
  EXPECT_GT(rate_kg_s[0], 1.15 * rate_kg_s[1]);
  EXPECT_GT(rate_kg_s[1], 2.0 * rate_kg_s[2]);

  const double static_before = plant.truth().static_kg;
  const auto together = open_then_settle(scene, plant, {0, 1, 2}, 1.0);
  double sum = 0.0;
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_GT(together[i], 0.2) << "ingredient " << i;
    sum += together[i];
  }
  EXPECT_NEAR(plant.truth().static_kg - static_before, sum, 1e-12 * (1.0 + sum));
  plant.advance(60.0);  // the platform rings down
  EXPECT_NEAR(plant.truth().force_n / scene.g, plant.truth().released_kg, 1e-4);
}

TEST(Ingredients, IdleIngredientsChangeNothingForIngredientZero) {
  // The batching scene with its valves 1 and 2 never opened doses exactly as the same scene
  // without them: each ingredient draws on its own random streams.
  const Scene batching = testing::shipped_scene("batching");
  Scene single = batching;
  single.ingredients.clear();
  Plant with(batching, 5);
  Plant without(single, 5);
  for (int jiffy = 0; jiffy < 600; ++jiffy) {
    if (jiffy == 50) {
      with.command_valve(ValveCommand::open, 0.0042);
      without.command_valve(ValveCommand::open, 0.0042);
    }
    if (jiffy == 250) {
      with.command_valve(ValveCommand::closed);
      without.command_valve(ValveCommand::closed);
    }
    with.advance(0.010);
    without.advance(0.010);
    ASSERT_EQ(with.sample().raw_counts, without.sample().raw_counts) << "jiffy " << jiffy;
    ASSERT_EQ(with.truth().force_n, without.truth().force_n) << "jiffy " << jiffy;
    ASSERT_EQ(with.truth().released_kg, without.truth().released_kg) << "jiffy " << jiffy;
  }
  EXPECT_GT(with.truth().released_kg, 1.0);
}

TEST(Ingredients, OneIngredientListedIsTheSceneWithoutTheKey) {
  const Scene plain = parse_scene_json(R"({"name": "x"})", "x.json");
  const Scene listed = parse_scene_json(R"({"name": "x", "ingredients": [{"material": "sand"}]})", "x.json");
  EXPECT_EQ(describe_scene(plain).size() + 5, describe_scene(listed).size());
  Plant a(plain, 3);
  Plant b(listed, 3);
  EXPECT_EQ(b.ingredient_count(), 1u);
  a.command_valve(ValveCommand::open);
  b.command_valve(ValveCommand::open);
  for (int jiffy = 0; jiffy < 200; ++jiffy) {
    a.advance(0.010);
    b.advance(0.010);
    ASSERT_EQ(a.sample().raw_counts, b.sample().raw_counts) << "jiffy " << jiffy;
  }
}

TEST(Ingredients, AValveTheSceneLacksIsRefused) {
  Plant plant(default_scene(), 1);
  EXPECT_EQ(plant.ingredient_count(), 1u);
  EXPECT_TRUE(plant.command_ingredient_valve(0, ValveCommand::open));
  EXPECT_FALSE(plant.command_ingredient_valve(1, ValveCommand::open));
  EXPECT_FALSE(plant.command_ingredient_valve(7, ValveCommand::open));
  EXPECT_EQ(plant.ingredient_valve_feedback(1), ValvePosition::closed);
}

TEST(Ingredients, EntriesOverrideTheBaseSceneAndBadOnesAreRefusedByName) {
  const Scene scene = parse_scene_json(
      R"({"name": "x", "silo": {"fill_kg": 12}, "ingredients": [
            {"material": "a", "silo": {"bore_m": 0.05}},
            {"material": "b", "valve": {"full_stroke_s": 0.3}, "column": {"fall_height_m": 1.5}}]})",
      "x.json");
  ASSERT_EQ(scene.ingredients.size(), 2u);
  EXPECT_EQ(scene.silo.bore_m, 0.05);  // entry 0 is the scene's own silo
  EXPECT_EQ(scene.ingredients[1].silo.bore_m, default_scene().silo.bore_m);
  EXPECT_EQ(scene.ingredients[1].silo.fill_kg, 12.0);  // from the base scene
  EXPECT_EQ(scene.ingredients[1].valve.full_stroke_s, 0.3);
  EXPECT_EQ(scene.ingredients[1].fall_height_m, 1.5);
  // Written out and read back, the same ingredients.
  const Scene again = parse_scene_json(scene_to_json(scene), "again.json");
  EXPECT_EQ(describe_scene(again), describe_scene(scene));

  auto refusal = [](const std::string& text) {
    try {
      parse_scene_json(text, "x.json");
    } catch (const std::runtime_error& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal(R"({"ingredients": [{"silo": {"bore": 1}}]})").find("ingredients[0].silo.bore"), std::string::npos);
  EXPECT_NE(refusal(R"({"ingredients": [{}, {"column": {"repose_angle_deg": 30}}]})").find("ingredients[1].column"),
            std::string::npos);
  EXPECT_NE(refusal(R"({"ingredients": [{}, {"silo": {"bore_m": -1}}]})").find("ingredients[1]: silo.bore_m"),
            std::string::npos);
  EXPECT_NE(refusal(R"({"ingredients": []})").find("ingredients"), std::string::npos);
  EXPECT_NE(refusal(R"({"ingredients": [{},{},{},{},{},{},{},{},{}]})").find("1 to 8"), std::string::npos);
  EXPECT_NE(refusal(R"({"components": ["hourglass"], "ingredients": [{}]})").find("hourglass"), std::string::npos);
}

}  // namespace
}  // namespace dynweigh::sim
