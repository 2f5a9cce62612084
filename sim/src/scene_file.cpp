#include "dynweigh/sim/scene_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <sys/stat.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "dynweigh/model/beverloo.hpp"
#include "dynweigh/model/bore_area.hpp"
#include "dynweigh/model/ideal_model.hpp"
#include "dynweigh/sim/components.hpp"
#include "scene_fields.hpp"

namespace dynweigh::sim {
namespace {

using nlohmann::json;

std::string format_number(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.10g", value);
  return text;
}

// Field names and values come from the file: a refusal quotes them on one printable line, not
// too long (found by fuzz/scene_fuzzer.cpp: a key "a\nb" made a two-line message).
std::string printable(const std::string& text) {
  constexpr std::size_t kMaxQuoted = 200;
  std::string out;
  for (const char c : text) {
    if (out.size() == kMaxQuoted) return out + "...";
    out.push_back(c >= 0x20 && c != 0x7f ? c : '?');
  }
  return out;
}

[[noreturn]] void reject(const std::string& origin, const std::string& field, const std::string& why) {
  throw std::runtime_error(origin + ": " + printable(field) + ": " + printable(why));
}

std::string dotted(const char* section, const char* key) {
  return *section ? std::string(section) + "." + key : std::string(key);
}

void check_range(const std::string& origin, const std::string& field, double value, const detail::FieldRange& r) {
  if (!std::isfinite(value)) reject(origin, field, "must be a finite number");
  const bool below = r.low_open ? value <= r.low : value < r.low;
  if (below || value > r.high) {
    reject(origin, field, std::string("must be ") + (r.low_open ? "> " : ">= ") + format_number(r.low) +
                              " and <= " + format_number(r.high) + " (got " + format_number(value) + ")");
  }
}

// Component names a file may list; the always-present ones are accepted for readability.
Component component_from_name(const std::string& origin, const std::string& name) {
  for (std::size_t i = 0; i < kComponentCount; ++i) {
    const auto c = static_cast<Component>(i);
    if (name == component_name(c)) return c;
  }
  reject(origin, "components", "unknown component '" + name + "'");
}

void apply_components(const json& list, Scene& scene, const std::string& origin) {
  if (!list.is_array()) reject(origin, "components", "must be an array of component names");
  ComponentSet wanted;
  for (const json& item : list) {
    if (!item.is_string()) reject(origin, "components", "must be an array of component names");
    wanted.add(component_from_name(origin, item.get<std::string>()));
  }
  scene.column.pile_grows = wanted.has(Component::pile);
  scene.pile_top.enabled = wanted.has(Component::pile_top);
  scene.avalanche.enabled = wanted.has(Component::avalanche);
  scene.platform.rigid = !wanted.has(Component::platform);
  scene.creep.enabled = wanted.has(Component::creep);
  scene.hourglass.enabled = wanted.has(Component::hourglass);
  if (!wanted.has(Component::impact_relaxation)) scene.impact.relaxation_s = 0.0;
  if ((scene.pile_top.enabled || scene.avalanche.enabled) && !scene.column.pile_grows) {
    reject(origin, "components", "pile_top and avalanche act on the pile: list 'pile' too");
  }
}

// The scene with ingredient `ingredient`'s silo, valve and height in place of its own: an ingredient
// is checked, described and written with the same field table as the scene.
Scene scene_of_ingredient(const Scene& scene, const IngredientParameters& ingredient) {
  Scene own = scene;
  own.ingredients.clear();
  own.silo = ingredient.silo;
  own.valve = ingredient.valve;
  own.column.fall_height_m = ingredient.fall_height_m;
  return own;
}

bool is_ingredient_field(const char* section, const char* key) {
  const std::string s = section;
  return s == "silo" || s == "valve" || (s == "column" && std::string(key) == "fall_height_m");
}

IngredientParameters parse_ingredient(const json& entry, const Scene& base, std::size_t index, const std::string& origin) {
  const std::string where = "ingredients[" + std::to_string(index) + "]";
  if (!entry.is_object()) reject(origin, where, "must be an object");
  IngredientParameters ingredient{"ingredient" + std::to_string(index), base.silo, base.valve, base.column.fall_height_m};
  Scene own = scene_of_ingredient(base, ingredient);
  for (auto it = entry.begin(); it != entry.end(); ++it) {
    if (it.key().rfind('_', 0) == 0) continue;
    if (it.key() == "material") {
      if (!it->is_string() || it->get<std::string>().empty()) reject(origin, where + ".material", "must be a non-empty string");
      ingredient.material = it->get<std::string>();
      continue;
    }
    if (!it->is_object()) reject(origin, where + "." + it.key(), "unknown field (an ingredient has material, silo, valve, column.fall_height_m)");
    for (auto inner = it->begin(); inner != it->end(); ++inner) {
      if (inner.key().rfind('_', 0) == 0) continue;
      const std::string name = where + "." + it.key() + "." + inner.key();
      bool found = false;
      detail::visit_scene_fields(own, [&](const char* section, const char* key, const char*, double& value,
                                          const detail::FieldRange&) {
        if (found || it.key() != section || inner.key() != key || !is_ingredient_field(section, key)) return;
        if (!inner->is_number()) reject(origin, name, "must be a number");
        value = inner->get<double>();
        found = true;
      });
      if (!found) reject(origin, name, "unknown field (an ingredient has material, silo, valve, column.fall_height_m)");
    }
  }
  ingredient.silo = own.silo;
  ingredient.valve = own.valve;
  ingredient.fall_height_m = own.column.fall_height_m;
  return ingredient;
}

// Entry i overrides the scene's silo, valve and fall height for ingredient i; entry 0 becomes the
// scene's own silo, valve and fall height.
void apply_ingredients(const json& list, Scene& scene, const std::string& origin) {
  if (!list.is_array() || list.empty() || list.size() > kMaxIngredients) {
    reject(origin, "ingredients", "must be an array of 1 to " + std::to_string(kMaxIngredients) + " ingredients");
  }
  scene.ingredients.clear();
  for (std::size_t i = 0; i < list.size(); ++i) scene.ingredients.push_back(parse_ingredient(list[i], scene, i, origin));
  scene.silo = scene.ingredients[0].silo;
  scene.valve = scene.ingredients[0].valve;
  scene.column.fall_height_m = scene.ingredients[0].fall_height_m;
}

}  // namespace

void validate_scene(const Scene& scene, const std::string& origin) {
  detail::visit_scene_fields(scene, [&](const char* section, const char* key, const char*, const double& value,
                                        const detail::FieldRange& range) {
    check_range(origin, dotted(section, key), value, range);
  });
  const double steps_per_jiffy = 0.010 / scene.internal_step_s;
  if (std::abs(steps_per_jiffy - std::round(steps_per_jiffy)) > 1e-6) {
    reject(origin, "internal_step_s", "must divide the 10 ms jiffy (got " + format_number(scene.internal_step_s) + ")");
  }
  if (scene.pile_top.enabled && scene.pile_top.flat_radius_m >= 0.5 * scene.column.container_diameter_m) {
    reject(origin, "pile_top.flat_radius_m", "must be smaller than the container's radius");
  }
  if (scene.silo.refill_below_kg > scene.silo.fill_kg) {
    reject(origin, "silo.refill_below_kg", "must not exceed silo.fill_kg, the level a refill stops at");
  }
  if (scene.hourglass.enabled && scene.silo.refill_below_kg > 0.0) {
    reject(origin, "silo.refill_below_kg", "the hourglass weighs its silo: it cannot be refilled");
  }
  if (scene.load_cell.capacity_kg * scene.load_cell.overload_fraction * scene.load_cell.counts_per_kg > 2e9) {
    reject(origin, "load_cell.capacity_kg", "its counts overflow a 32-bit ADC word");
  }
  if (scene.ingredients.empty()) return;
  if (scene.ingredients.size() > kMaxIngredients) {
    reject(origin, "ingredients", "at most " + std::to_string(kMaxIngredients) + " ingredients");
  }
  if (scene.hourglass.enabled) reject(origin, "ingredients", "the hourglass weighs its one silo: it has no ingredients");
  for (std::size_t i = 0; i < scene.ingredients.size(); ++i) {
    validate_scene(scene_of_ingredient(scene, scene.ingredients[i]), origin + ": ingredients[" + std::to_string(i) + "]");
  }
}

Scene parse_scene_json(const std::string& text, const std::string& origin) {
  json document;
  try {
    document = json::parse(text);
  } catch (const json::exception& error) {  // parse_error, and out_of_range for a number like 1e400
    throw std::runtime_error(origin + ": not valid JSON (" + printable(error.what()) + ")");
  }
  if (!document.is_object()) throw std::runtime_error(origin + ": a scene is a JSON object");

  Scene scene = default_scene();
  std::set<std::string> known_sections{"name", "source", "components", "ingredients"};
  std::set<std::string> used;
  detail::visit_scene_fields(scene, [&](const char* section, const char* key, const char*, double& value,
                                        const detail::FieldRange&) {
    const json* holder = &document;
    if (*section) {
      known_sections.insert(section);
      const auto it = document.find(section);
      if (it == document.end()) return;
      if (!it->is_object()) reject(origin, section, "must be an object");
      holder = &*it;
    } else {
      known_sections.insert(key);
    }
    const auto field = holder->find(key);
    if (field == holder->end()) return;
    if (!field->is_number()) reject(origin, dotted(section, key), "must be a number");
    value = field->get<double>();
    used.insert(dotted(section, key));
  });

  // Every key of the file must be one the scene knows: a typo is an error, not a silent default.
  // Keys that start with '_' are notes (sources, reasons): JSON has no comments.
  for (auto it = document.begin(); it != document.end(); ++it) {
    if (it.key().rfind('_', 0) == 0) continue;
    if (!known_sections.count(it.key())) reject(origin, it.key(), "unknown field");
    if (it->is_object() && it.key() != "ingredients") {
      for (auto inner = it->begin(); inner != it->end(); ++inner) {
        if (inner.key().rfind('_', 0) == 0) continue;
        const std::string name = it.key() + "." + inner.key();
        if (!used.count(name)) reject(origin, name, "unknown field");
      }
    }
  }
  if (const auto name = document.find("name"); name != document.end()) {
    if (!name->is_string() || name->get<std::string>().empty()) reject(origin, "name", "must be a non-empty string");
    scene.name = name->get<std::string>();
  }
  if (const auto source = document.find("source"); source != document.end()) {
    if (!source->is_string()) reject(origin, "source", "must be a string");
    scene.source = source->get<std::string>();
  }
  if (const auto list = document.find("components"); list != document.end()) apply_components(*list, scene, origin);
  if (const auto list = document.find("ingredients"); list != document.end()) apply_ingredients(*list, scene, origin);
  validate_scene(scene, origin);
  return scene;
}

Scene load_scene_file(const std::string& path) {
  // Scene files are a few kB. Read at most one byte past the limit, so a wrong path (a huge log,
  // a sparse file, /dev/zero, a FIFO) is refused at once instead of read into memory.
  constexpr std::size_t kMaxSceneFileBytes = 1 << 20;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot read the scene file");
  std::string text(kMaxSceneFileBytes + 1, '\0');
  in.read(text.data(), std::streamsize(text.size()));
  if (in.bad()) throw std::runtime_error(path + ": cannot read the scene file");
  text.resize(std::size_t(in.gcount()));
  if (text.size() > kMaxSceneFileBytes) {
    throw std::runtime_error(path + ": more than " + std::to_string(kMaxSceneFileBytes) + " bytes, not a scene file");
  }
  return parse_scene_json(text, path);
}

std::string scene_to_json(const Scene& scene, const std::string& notes_json) {
  json document = json::object();
  document["name"] = scene.name;
  document["source"] = scene.source;
  if (!notes_json.empty()) document["_calibration"] = json::parse(notes_json);
  json components = json::array();
  const std::string names = components_of(scene).names();
  for (std::size_t begin = 0; begin < names.size();) {
    const std::size_t comma = std::min(names.find(',', begin), names.size());
    components.push_back(names.substr(begin, comma - begin));
    begin = comma + 1;
  }
  document["components"] = components;
  detail::visit_scene_fields(scene, [&](const char* section, const char* key, const char*, const double& value,
                                        const detail::FieldRange&) {
    if (*section) {
      document[section][key] = value;
    } else {
      document[key] = value;
    }
  });
  if (!scene.ingredients.empty()) {
    json ingredients = json::array();
    for (const IngredientParameters& ingredient : scene.ingredients) {
      json entry = json::object();
      entry["material"] = ingredient.material;
      const Scene own = scene_of_ingredient(scene, ingredient);
      detail::visit_scene_fields(own,
                                 [&](const char* section, const char* key, const char*, const double& value,
                                     const detail::FieldRange&) {
                                   if (is_ingredient_field(section, key)) entry[section][key] = value;
                                 });
      ingredients.push_back(entry);
    }
    document["ingredients"] = ingredients;
  }
  return document.dump(2) + "\n";
}

namespace {
// An installed program (the Debian package, `cmake --install`, or a package unpacked anywhere)
// finds the scenes installed beside it: <its bin folder>/<DYNWEIGH_SCENES_FROM_BINDIR>.
std::string installed_scenes_directory() {
#ifdef DYNWEIGH_SCENES_FROM_BINDIR
  char exe[4096];
  const ssize_t n = ::readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n <= 0) return "";
  const std::string program(exe, std::size_t(n));
  const std::string dir = program.substr(0, program.rfind('/') + 1) + DYNWEIGH_SCENES_FROM_BINDIR;
  struct stat info {};
  if (::stat(dir.c_str(), &info) == 0 && S_ISDIR(info.st_mode)) return dir;
#endif
  return "";
}
}  // namespace

std::string scenes_directory() {
  if (const char* env = std::getenv("DYNWEIGH_SCENES"); env && *env) return env;
  if (std::string installed = installed_scenes_directory(); !installed.empty()) return installed;
#ifdef DYNWEIGH_SCENES_DIR
  return DYNWEIGH_SCENES_DIR;
#else
  return "scenes";
#endif
}

std::vector<std::pair<std::string, std::string>> describe_scene(const Scene& scene) {
  std::vector<std::pair<std::string, std::string>> lines;
  lines.emplace_back("scene", scene.name);
  detail::visit_scene_fields(scene, [&](const char*, const char*, const char* describe_key, const double& value,
                                        const detail::FieldRange&) {
    lines.emplace_back(describe_key, format_number(value));
  });
  lines.emplace_back("pile_grows", scene.column.pile_grows ? "1" : "0");
  lines.emplace_back("platform_rigid", scene.platform.rigid ? "1" : "0");
  lines.emplace_back("components", components_of(scene).names());

  // What the ideal model (thesis ch. 1, corrected sign) makes of these parameters at full open.
  const model::BeverlooMaterial<double> material{scene.silo.beverloo_C, scene.silo.beverloo_k, scene.silo.grain_d_m,
                                                 scene.silo.bulk_density};
  const double rate = model::beverloo_discharge_kg_s(material, scene.g, scene.silo.bore_m);
  const double v0 = model::outflow_speed(rate, model::bore_area_m2(scene.silo.bore_m), scene.silo.bulk_density);
  const double h = scene.column.fall_height_m;
  lines.emplace_back("full_open_rate_kg_s", format_number(rate));
  lines.emplace_back("outflow_speed_m_s", format_number(v0));
  lines.emplace_back("fall_time_s", format_number(model::fall_time(v0, scene.g, h)));
  lines.emplace_back("in_flight_kg", format_number(model::mass_in_flight(rate, v0, scene.g, h)));
  lines.emplace_back("impulse_force_n", format_number(model::impulse_force(rate, v0, scene.g, h)));
  lines.emplace_back("excess_at_close_kg", format_number(model::reading_excess_at_close_kg(rate, v0, scene.g)));
  if (!scene.ingredients.empty()) {
    lines.emplace_back("ingredients", std::to_string(scene.ingredients.size()));
    for (std::size_t i = 0; i < scene.ingredients.size(); ++i) {
      const IngredientParameters& ingredient = scene.ingredients[i];
      const std::string prefix = "ingredient" + std::to_string(i) + "_";
      const model::BeverlooMaterial<double> own{ingredient.silo.beverloo_C, ingredient.silo.beverloo_k,
                                                ingredient.silo.grain_d_m, ingredient.silo.bulk_density};
      lines.emplace_back(prefix + "material", ingredient.material);
      lines.emplace_back(prefix + "bulk_density", format_number(ingredient.silo.bulk_density));
      lines.emplace_back(prefix + "full_open_rate_kg_s",
                         format_number(model::beverloo_discharge_kg_s(own, scene.g, ingredient.silo.bore_m)));
      lines.emplace_back(prefix + "fall_height_m", format_number(ingredient.fall_height_m));
    }
  }
  lines.emplace_back("source", scene.source);
  return lines;
}

}  // namespace dynweigh::sim
