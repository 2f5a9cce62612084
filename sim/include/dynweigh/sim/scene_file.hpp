#pragma once
// Scenes as JSON files (host only; may throw). A file holds the fields it changes from the
// default scene, grouped by component, plus the list of optional components it runs:
//   { "name": "tall-drop", "source": "...", "components": ["pile", "impact_relaxation", "platform"],
//     "column": { "fall_height_m": 3.0 } }
// Keys starting with "_" are notes (sources). Unknown fields, wrong types and values out of range are rejected with a message naming the
// field, e.g. `scenes/x.json: column.fall_height_m: must be > 0 (got -1)`.
#include <string>
#include <utility>
#include <vector>

#include "dynweigh/sim/scene.hpp"

namespace dynweigh::sim {

Scene parse_scene_json(const std::string& text, const std::string& origin);
Scene load_scene_file(const std::string& path);

// The scenes directory: $DYNWEIGH_SCENES, else the installed scenes beside the running program
// (../share/dynweigh/scenes from its bin folder) when they exist, else the source tree's scenes/.
std::string scenes_directory();

// The scene's resolved parameters in SI units as key=value pairs, ending with the components it
// runs and the ideal-model figures its parameters imply (flow, v0, fall time, mdot v0 / g).
std::vector<std::pair<std::string, std::string>> describe_scene(const Scene& scene);

// The scene as a complete scene file (every field, the component list, name and source), which
// parse_scene_json reads back to the same scene. `notes_json`, if not empty, is a JSON object
// written under the note key "_calibration" (the figures a calibration measured).
std::string scene_to_json(const Scene& scene, const std::string& notes_json = "");

// Checks ranges and cross-field constraints of a scene built in code; throws naming the field.
void validate_scene(const Scene& scene, const std::string& origin);

}  // namespace dynweigh::sim
