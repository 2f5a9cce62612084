#include "dynweigh/firmware/material_table.hpp"

#include <cstring>

namespace dynweigh::firmware {
namespace {

bool name_character(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
         c == '.';
}

bool in_range(ParameterId id, float value) {
  const ParameterSpec& spec = parameter_spec(id);
  return value >= spec.minimum && value <= spec.maximum;
}

}  // namespace

MaterialTable::MaterialTable(const Parameters& parameters) {
  define(0);
  materials_[0].density = parameters.get(ParameterId::density);
  materials_[0].class_x = parameters.get(ParameterId::oiml_class);
}

bool MaterialTable::valid_name(const char* name) {
  std::size_t n = 0;
  for (; name[n]; ++n) {
    if (n >= Material::kNameBytes - 1 || !name_character(name[n])) return false;
  }
  return n > 0;
}

bool MaterialTable::valid(const Material& m) {
  bool ended = false;
  for (char c : m.name) ended = ended || c == '\0';
  return m.defined && ended && valid_name(m.name) && in_range(ParameterId::density, m.density) &&
         in_range(ParameterId::oiml_class, m.class_x);
}

void MaterialTable::define(std::size_t n) {
  Material& m = materials_[n];
  if (m.defined) return;
  m = Material{};
  m.defined = true;
  std::strcpy(m.name, "material");
  if (n >= 10) m.name[8] = char('0' + n / 10), m.name[9] = char('0' + n % 10);
  else m.name[8] = char('0' + n);
  m.density = parameter_spec(ParameterId::density).default_value;
  m.class_x = parameter_spec(ParameterId::oiml_class).default_value;
}

bool MaterialTable::rename(std::size_t n, const char* name) {
  if (!valid_name(name)) return false;
  define(n);
  std::memset(materials_[n].name, 0, Material::kNameBytes);
  std::strcpy(materials_[n].name, name);
  return true;
}

bool MaterialTable::set_density(std::size_t n, float density) {
  if (!in_range(ParameterId::density, density)) return false;
  define(n);
  materials_[n].density = density;
  return true;
}

bool MaterialTable::set_class(std::size_t n, float class_x) {
  if (!in_range(ParameterId::oiml_class, class_x)) return false;
  define(n);
  materials_[n].class_x = class_x;
  return true;
}

void MaterialTable::select(std::size_t n, Parameters& parameters) {
  define(n);
  selected_ = n;
  parameters.set(ParameterId::density, materials_[n].density);
  parameters.set(ParameterId::oiml_class, materials_[n].class_x);
}

void MaterialTable::forget_learned() {
  for (Material& m : materials_) {
    m.learned = MaterialLearning{};
    m.pulses = TopUpPulseLearning{};
    m.valve_slowest_dead_ms = 0.0f;
  }
}

void MaterialTable::follow_parameter(ParameterId id, const Parameters& parameters) {
  if (id == ParameterId::density) materials_[selected_].density = parameters.get(id);
  if (id == ParameterId::oiml_class) materials_[selected_].class_x = parameters.get(id);
}

}  // namespace dynweigh::firmware
