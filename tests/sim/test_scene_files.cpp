// Scenes as JSON files: every shipped scene loads and validates, the files of the built-in scenes
// say exactly what the code says, and a malformed scene is rejected with the field named.
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "dynweigh/sim/components.hpp"
#include "dynweigh/sim/plant.hpp"
#include "dynweigh/sim/scene_file.hpp"
#include "dynweigh/sim/valve_schedule.hpp"

namespace dynweigh::sim {
namespace {

std::string rejection(const std::string& json) {
  try {
    parse_scene_json(json, "test.json");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(SceneFiles, ShipsTheScenesTheIssueNames) {
  const auto names = scene_names();
  for (const char* wanted : {"default", "ideal", "hourglass", "slow-valve", "tall-drop", "small-dose", "fine-powder"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), wanted), names.end()) << wanted;
  }
}

TEST(SceneFiles, EveryShippedSceneLoadsUnderItsOwnName) {
  for (const std::string& name : scene_names()) {
    const auto scene = scene_by_name(name);
    ASSERT_TRUE(scene.has_value()) << name;
    EXPECT_EQ(scene->name, name);
    EXPECT_NO_THROW(validate_scene(*scene, name));
  }
}

TEST(SceneFiles, DefaultAndIdealFilesEqualTheBuiltInScenes) {
  EXPECT_EQ(describe_scene(load_scene_file(scenes_directory() + "/default.json")), describe_scene(default_scene()));
  EXPECT_EQ(describe_scene(load_scene_file(scenes_directory() + "/ideal.json")), describe_scene(ideal_scene()));
}

TEST(SceneFiles, ScenesDifferWhereTheirNamesSay) {
  EXPECT_DOUBLE_EQ(scene_by_name("tall-drop")->column.fall_height_m, 3.0);
  EXPECT_DOUBLE_EQ(scene_by_name("small-dose")->silo.bore_m, 0.030);
  EXPECT_DOUBLE_EQ(scene_by_name("slow-valve")->valve.full_stroke_s, 0.200);
  EXPECT_TRUE(scene_by_name("hourglass")->hourglass.enabled);
  const Scene powder = *scene_by_name("fine-powder");
  const Scene sand = default_scene();
  EXPECT_LT(Plant(powder, 1).full_open_rate_kg_s(), 0.5 * Plant(sand, 1).full_open_rate_kg_s());
  EXPECT_GT(powder.impact.relaxation_s, 4 * sand.impact.relaxation_s);
}

TEST(SceneFiles, DescribeNamesTheResolvedParametersAndComponents) {
  const auto lines = describe_scene(*scene_by_name("tall-drop"));
  auto value = [&](const std::string& key) {
    for (const auto& [k, v] : lines) {
      if (k == key) return v;
    }
    return std::string("<missing>");
  };
  for (const char* key : {"g", "fall_height_m", "bore_m", "bulk_density", "beverloo_C", "beverloo_k", "grain_d_m",
                          "platform_hz", "platform_zeta", "components"}) {
    EXPECT_NE(value(key), "<missing>") << key;
  }
  EXPECT_EQ(value("fall_height_m"), "3");
  EXPECT_EQ(value("components"), components_of(*scene_by_name("tall-drop")).names());
  EXPECT_EQ(describe_scene(ideal_scene()).size(), lines.size());
}

TEST(SceneFiles, FullOpenRateInTheDescriptionIsBeverloosFigure) {
  for (const auto& [key, value] : describe_scene(default_scene())) {
    if (key == "full_open_rate_kg_s") {
      EXPECT_NEAR(std::stod(value), 2.41, 0.01);  // docs/physics.md
    }
    if (key == "excess_at_close_kg") {
      EXPECT_NEAR(std::stod(value), 0.135, 0.001);  // docs/physics.md
    }
  }
}

TEST(SceneFiles, RejectsMalformedScenesNamingTheField) {
  EXPECT_NE(rejection("{\"column\": {\"fall_height\": 3}}").find("column.fall_height: unknown field"), std::string::npos);
  EXPECT_NE(rejection("{\"colum\": {}}").find("colum: unknown field"), std::string::npos);
  EXPECT_NE(rejection("{\"column\": {\"fall_height_m\": \"3\"}}").find("column.fall_height_m: must be a number"),
            std::string::npos);
  EXPECT_NE(rejection("{\"column\": {\"fall_height_m\": -1}}").find("column.fall_height_m: must be > 0"),
            std::string::npos);
  EXPECT_NE(rejection("{\"silo\": 5}").find("silo: must be an object"), std::string::npos);
  EXPECT_NE(rejection("{\"components\": [\"pile\", \"levitation\"]}").find("components: unknown component"),
            std::string::npos);
  EXPECT_NE(rejection("{\"components\": [\"avalanche\"]}").find("components:"), std::string::npos);
  EXPECT_NE(rejection("{\"internal_step_s\": 0.003}").find("internal_step_s: must divide"), std::string::npos);
  EXPECT_NE(rejection("{\"name\": 3}").find("name:"), std::string::npos);
  EXPECT_NE(rejection("[1, 2]").find("a scene is a JSON object"), std::string::npos);
  EXPECT_NE(rejection("{\"g\": 9.81,").find("not valid JSON"), std::string::npos);
  EXPECT_EQ(rejection("{\"_note\": \"why\", \"column\": {\"_source\": \"x\", \"fall_height_m\": 2}}"), "");
}

TEST(SceneFiles, ComponentsListSwitchesTheOptionalComponents) {
  const Scene bare = parse_scene_json("{\"components\": [\"silo\", \"valve\", \"column\", \"load_cell\"]}", "t");
  EXPECT_FALSE(bare.column.pile_grows);
  EXPECT_TRUE(bare.platform.rigid);
  EXPECT_EQ(bare.impact.relaxation_s, 0.0);
  EXPECT_EQ(components_of(bare).names(), "silo,valve,column,load_cell");
  const Scene full = parse_scene_json(
      "{\"components\": [\"pile\", \"pile_top\", \"avalanche\", \"impact_relaxation\", \"platform\", \"creep\", "
      "\"hourglass\"]}",
      "t");
  EXPECT_EQ(components_of(full).names(),
            "silo,valve,column,pile,pile_top,impact_relaxation,avalanche,platform,load_cell,creep,hourglass");
}

TEST(ValveSchedule, ParsesOpenHalfCloseInJiffyOrder) {
  const auto events = parse_valve_schedule("close@600,open@50,half@400");
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0].jiffy, 50u);
  EXPECT_EQ(events[0].command, ValveCommand::open);
  EXPECT_EQ(events[1].command, ValveCommand::half);
  EXPECT_EQ(events[2].command, ValveCommand::closed);
  EXPECT_THROW(parse_valve_schedule("open@x"), std::invalid_argument);
  EXPECT_THROW(parse_valve_schedule("shut@5"), std::invalid_argument);
  EXPECT_THROW(parse_valve_schedule("open50"), std::invalid_argument);
  EXPECT_THROW(parse_valve_schedule("open@5,,close@9"), std::invalid_argument);
}

}  // namespace
}  // namespace dynweigh::sim
