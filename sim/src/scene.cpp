#include "dynweigh/sim/scene.hpp"

namespace dynweigh::sim {

Scene default_scene() { return Scene{}; }

Scene ideal_scene() {
  Scene scene;
  scene.name = "ideal";
  scene.silo.alpha_start = 1.0;
  scene.silo.fluctuation_rms = 0.0;
  scene.valve = {0.0, 0.0, 0.0};
  scene.column.pile_grows = false;
  scene.impact.relaxation_s = 0.0;
  scene.platform.rigid = true;
  scene.load_cell.noise_counts_rms = 0.0;
  return scene;
}

std::optional<Scene> scene_by_name(const std::string& name) {
  if (name == "default") return default_scene();
  if (name == "ideal") return ideal_scene();
  return std::nullopt;
}

std::vector<std::string> scene_names() { return {"default", "ideal"}; }

}  // namespace dynweigh::sim
