#include "dynweigh/sim/scene.hpp"

#include <algorithm>
#include <dirent.h>
#include <sys/stat.h>

#include "dynweigh/sim/scene_file.hpp"

namespace dynweigh::sim {
namespace {

bool ends_with(const std::string& text, const std::string& tail) {
  return text.size() >= tail.size() && text.compare(text.size() - tail.size(), tail.size(), tail) == 0;
}

bool file_exists(const std::string& path) {
  struct stat info {};
  return ::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

}  // namespace

Scene default_scene() { return Scene{}; }

Scene ideal_scene() {
  Scene scene;
  scene.name = "ideal";
  scene.source = "thesis chapter 1: instant valve, constant h, rigid scale, no noise";
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
  if (ends_with(name, ".json")) return load_scene_file(name);
  if (name.empty() || name.find('/') != std::string::npos) return std::nullopt;
  const std::string path = scenes_directory() + "/" + name + ".json";
  if (file_exists(path)) return load_scene_file(path);
  if (name == "default") return default_scene();
  if (name == "ideal") return ideal_scene();
  return std::nullopt;
}

std::vector<std::string> scene_names() {
  std::vector<std::string> names{"default", "ideal"};
  if (DIR* dir = ::opendir(scenes_directory().c_str())) {
    while (const dirent* entry = ::readdir(dir)) {
      const std::string file = entry->d_name;
      if (ends_with(file, ".json") && file.size() > 5) names.push_back(file.substr(0, file.size() - 5));
    }
    ::closedir(dir);
  }
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  return names;
}

}  // namespace dynweigh::sim
