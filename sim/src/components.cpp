#include "dynweigh/sim/components.hpp"

#include "dynweigh/sim/scene.hpp"

namespace dynweigh::sim {

const char* component_name(Component component) {
  switch (component) {
    case Component::silo: return "silo";
    case Component::valve: return "valve";
    case Component::column: return "column";
    case Component::pile: return "pile";
    case Component::pile_top: return "pile_top";
    case Component::impact_relaxation: return "impact_relaxation";
    case Component::avalanche: return "avalanche";
    case Component::platform: return "platform";
    case Component::load_cell: return "load_cell";
    case Component::creep: return "creep";
    case Component::hourglass: return "hourglass";
  }
  return "?";
}

std::string ComponentSet::names() const {
  std::string out;
  for (std::size_t i = 0; i < kComponentCount; ++i) {
    const auto c = static_cast<Component>(i);
    if (!has(c)) continue;
    if (!out.empty()) out += ',';
    out += component_name(c);
  }
  return out;
}

ComponentSet components_of(const Scene& scene) {
  ComponentSet set;
  set.add(Component::silo);
  set.add(Component::valve);
  set.add(Component::column);
  set.add(Component::load_cell);
  // The pile top is what the flattening and the avalanches act on: both need a growing pile.
  if (scene.column.pile_grows) {
    set.add(Component::pile);
    if (scene.pile_top.enabled) set.add(Component::pile_top);
    if (scene.avalanche.enabled) set.add(Component::avalanche);
  }
  if (scene.impact.relaxation_s > 0.0) set.add(Component::impact_relaxation);
  if (!scene.platform.rigid) set.add(Component::platform);
  if (scene.creep.enabled) set.add(Component::creep);
  if (scene.hourglass.enabled) set.add(Component::hourglass);
  return set;
}

}  // namespace dynweigh::sim
