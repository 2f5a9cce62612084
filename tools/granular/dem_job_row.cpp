#include "dem_job_row.hpp"

#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace dynweigh::tools {

using granular::DemJob;
using granular::DemJobKind;
using granular::DemJobResult;

namespace {

std::string number(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

double parse_number(const std::string& name, const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0') throw std::runtime_error("DEM row field " + name + " holds '" + text + "', not a number");
  return value;
}

// Every field of a result, in the row's order, for both directions: `scalar(name, double&)`,
// `count(name, std::int64_t&)`, `series(name, std::vector<double>&)`. The job itself is not in the
// row: the reader has it from the job list.
template <typename Result, typename Visitor>
void visit_fields(Result& r, Visitor& v) {
  v.series("time_s", r.run.time_s);
  v.series("force_n", r.run.force_n);
  v.series("released_kg", r.run.released_kg);
  v.scalar("outflow_mean_speed", r.run.outflow.mean_speed);
  v.scalar("outflow_peak_speed", r.run.outflow.peak_speed);
  v.scalar("outflow_alpha", r.run.outflow.alpha);
  v.scalar("outflow_sampled_discs", r.run.outflow.sampled_discs);
  v.scalar("grain_diameter_m", r.run.grain_diameter_m);
  v.scalar("disc_mass_kg", r.run.disc_mass_kg);
  v.scalar("slot_depth_m", r.run.slot_depth_m);
  v.scalar("bed_bulk_density", r.run.bed_bulk_density);
  v.scalar("released_total_kg", r.run.released_total_kg);
  v.scalar("lost_kg", r.run.lost_kg);
  v.scalar("settle_s", r.run.settle_s);
  v.count("discs", r.run.discs);
  v.count("steps", r.run.steps);
  v.scalar("particle_steps", r.run.particle_steps);
  v.scalar("cpu_seconds", r.run.cpu_seconds);
  v.scalar("steady_rate_kg_s", r.steady_rate_kg_s);
  v.scalar("rate_per_depth_kg_s_m", r.rate_per_depth_kg_s_m);
  v.flag("features_valid", r.features.valid);
  v.scalar("dead_time_s", r.features.dead_time_s);
  v.scalar("impulse_n", r.features.impulse_n);
  v.scalar("slope_n_s", r.features.slope_n_s);
  v.scalar("relaxation_s", r.features.relaxation_s);
  v.scalar("final_n", r.features.final_n);
}

struct Encoder {
  std::string row;
  void name(const char* field) { row += (row.empty() ? "" : " ") + std::string(field) + "="; }
  void scalar(const char* field, double value) {
    name(field);
    row += number(value);
  }
  void count(const char* field, std::int64_t value) {
    name(field);
    row += std::to_string(value);
  }
  void flag(const char* field, bool value) { count(field, value ? 1 : 0); }
  void series(const char* field, const std::vector<double>& values) {
    name(field);
    row += std::to_string(values.size());
    for (const double value : values) row += "," + number(value);
  }
};

// Reads the fields in the order the encoder wrote them: a row of another layout fails on its
// first misplaced name.
struct Decoder {
  std::istringstream words;
  std::string value_of(const char* field) {
    std::string word;
    if (!(words >> word)) throw std::runtime_error(std::string("DEM row lacks field ") + field);
    const std::string prefix = std::string(field) + "=";
    if (word.compare(0, prefix.size(), prefix) != 0) {
      throw std::runtime_error("DEM row has '" + word.substr(0, 40) + "' where " + field + " belongs");
    }
    return word.substr(prefix.size());
  }
  void scalar(const char* field, double& value) { value = parse_number(field, value_of(field)); }
  void count(const char* field, std::int64_t& value) {
    value = static_cast<std::int64_t>(parse_number(field, value_of(field)));
  }
  void flag(const char* field, bool& value) { value = parse_number(field, value_of(field)) != 0; }
  void series(const char* field, std::vector<double>& values) {
    std::istringstream items(value_of(field));
    std::string item;
    std::getline(items, item, ',');
    const auto size = static_cast<std::size_t>(parse_number(field, item));
    values.clear();
    values.reserve(size);
    while (std::getline(items, item, ',')) values.push_back(parse_number(field, item));
    if (values.size() != size) throw std::runtime_error(std::string("DEM row field ") + field + " is cut short");
  }
};

}  // namespace

std::string dem_job_key(const DemJob& job) {
  if (job.kind == DemJobKind::scene_dose) return "dose seed=" + std::to_string(job.seed);
  return "discharge orifice_discs=" + number(job.config.discs_across_orifice) + " seed=" + std::to_string(job.seed);
}

std::string encode_dem_job_row(const DemJobResult& result) {
  Encoder encoder;
  visit_fields(result, encoder);
  return encoder.row;
}

DemJobResult decode_dem_job_row(const DemJob& job, const std::string& row) {
  DemJobResult result;
  result.job = job;
  Decoder decoder{std::istringstream(row)};
  visit_fields(result, decoder);
  std::string rest;
  if (decoder.words >> rest) throw std::runtime_error("DEM row has an unknown field '" + rest.substr(0, 40) + "'");
  return result;
}

}  // namespace dynweigh::tools
