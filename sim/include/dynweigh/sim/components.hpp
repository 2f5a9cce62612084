#pragma once
// The components a plant can be built from, and which of them a scene needs. A component whose
// output nothing reads is neither built nor stepped (the thesis' "skip what a scene doesn't
// need"): a rigid scale has no platform, a constant h has no pile, an instant impact no relaxation.
#include <cstddef>
#include <cstdint>
#include <string>

namespace dynweigh::sim {

struct Scene;

enum class Component : std::uint8_t {
  silo,               // Beverloo outflow, alpha settling, flow fluctuation, running empty
  valve,              // pneumatic slide gate: dead time, stroke, half-open stage
  column,             // falling parcels from orifice to pile top
  pile,               // pile height from mass, repose angle and container (h falls)
  pile_top,           // flattened and dented top under the stream
  impact_relaxation,  // dispersion of landing grains
  avalanche,          // F_a of thesis example 3.2
  platform,           // mass-spring-damper scale platform
  load_cell,          // gain, offset, noise, quantization, overload
  creep,              // load-cell creep
  hourglass,          // silo and container on the scale (a configuration, not stepped)
};
inline constexpr std::size_t kComponentCount = 11;

const char* component_name(Component component);

class ComponentSet {
 public:
  bool has(Component c) const { return (bits_ >> static_cast<unsigned>(c)) & 1u; }
  void add(Component c) { bits_ |= 1u << static_cast<unsigned>(c); }
  // Comma-separated names in enum order, e.g. "silo,valve,column,load_cell".
  std::string names() const;

 private:
  std::uint32_t bits_ = 0;
};

// What a scene runs; the plant builds exactly these.
ComponentSet components_of(const Scene& scene);

}  // namespace dynweigh::sim
