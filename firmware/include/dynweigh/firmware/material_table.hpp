#pragma once
// The materials a plant doses: up to kMaterials, each with a name, its bulk density's first guess
// and the OIML R61 class its fills are judged by. One is selected; its density and class are the
// `density` and `class` parameters a dose uses (selecting one copies them there, and `param density`
// or `param class` edits the selected one's). Material 0 always exists. What the model strategy's
// fills measured is kept per material (material_learning.hpp); what the learn strategy's table and
// the baselines learn is one set for all.
#include <cstddef>
#include <cstdint>

#include "dynweigh/firmware/material_learning.hpp"
#include "dynweigh/firmware/parameters.hpp"
#include "dynweigh/firmware/top_up_pulse_learning.hpp"

namespace dynweigh::firmware {

struct Material {
  static constexpr std::size_t kNameBytes = 16;  // 15 characters and the terminating NUL
  bool defined = false;
  char name[kNameBytes] = {};
  float density = 0.0f;  // kg/m^3, the `density` parameter's range
  float class_x = 0.0f;  // X(x), the `class` parameter's range
  MaterialLearning learned{};
  TopUpPulseLearning pulses{};  // what its top-up pulses taught
  // The slowest dead time the valve's feedback showed on its doses, ms (0: none yet): the fault
  // supervisor's leave limit after a restart (fault_supervisor.hpp, expect_dead_time_ms).
  float valve_slowest_dead_ms = 0.0f;
};

class MaterialTable {
 public:
  static constexpr std::size_t kMaterials = 16;

  // Material 0 defined from `parameters` (its density and class), selected; the others undefined.
  MaterialTable() : MaterialTable(Parameters{}) {}
  explicit MaterialTable(const Parameters& parameters);

  const Material& at(std::size_t n) const { return materials_[n]; }
  std::size_t selected() const { return selected_; }

  // Letters, digits, '_', '-' and '.', 1 to 15 of them: a name a console line keeps as one word.
  static bool valid_name(const char* name);
  // A defined entry the commands could have made: a NUL-ended valid name, density and class in range.
  static bool valid(const Material& material);
  // Defines material `n` if it is not (named "material<n>", with the parameters' defaults).
  void define(std::size_t n);
  bool rename(std::size_t n, const char* name);
  // False if `density` is outside the `density` parameter's range.
  bool set_density(std::size_t n, float density);
  bool set_class(std::size_t n, float class_x);
  // Selects `n` (defining it) and copies its density and class into `parameters`.
  void select(std::size_t n, Parameters& parameters);
  // A `param density` or `param class` just set: the selected material takes it.
  void follow_parameter(ParameterId id, const Parameters& parameters);

  // What the selected material's last certified model or learn fill left learned.
  void keep_learned(const MaterialLearning& learned) { materials_[selected_].learned = learned; }
  // What the selected material's top-up pulses taught.
  void keep_pulses(const TopUpPulseLearning& pulses) { materials_[selected_].pulses = pulses; }
  // The slowest dead time the valve's feedback showed on the selected material's doses.
  void keep_valve_slowest_dead_ms(float dead_ms) { materials_[selected_].valve_slowest_dead_ms = dead_ms; }
  // `learn reset`: every material's fills are forgotten.
  void forget_learned();

  // For the settings record: restores an entry as stored (checked by the caller) and the selection.
  void restore(std::size_t n, const Material& material) { materials_[n] = material; }
  void restore_selection(std::size_t n) { selected_ = n; }

 private:
  Material materials_[kMaterials];
  std::size_t selected_ = 0;
};

}  // namespace dynweigh::firmware
