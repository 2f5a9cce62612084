#include "series_row.hpp"

#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <sstream>
#include <stdexcept>

namespace dynweigh::tools {
namespace {

std::string number(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

struct Field {
  const char* name;
  double SeriesResult::*value;
};

constexpr Field kFields[] = {
    {"time_ratio_mean", &SeriesResult::time_ratio_mean},
    {"time_ratio_max", &SeriesResult::time_ratio_max},
    {"bias_g", &SeriesResult::bias_g},
    {"sd_g", &SeriesResult::sd_g},
    {"max_deviation_g", &SeriesResult::max_deviation_g},
    {"worst_reported_vs_true_g", &SeriesResult::worst_reported_vs_true_g},
    {"oiml_class", &SeriesResult::oiml_class},
};

}  // namespace

std::string series_key(const SeriesSpec& spec, const std::vector<Scenario>& scenarios) {
  return std::string("strategy=") + bench_strategy_name(spec.strategy) + " knob=" + number(spec.knob) +
         " scene=" + scenarios[spec.scenario].name + " target_g=" + number(spec.target_g);
}

std::string encode_series_row(const SeriesResult& result) {
  std::string row = "fills=" + std::to_string(result.fills) + " failed=" + std::to_string(result.failed);
  for (const Field& field : kFields) row += std::string(" ") + field.name + "=" + number(result.*field.value);
  return row;
}

SeriesResult decode_series_row(const SeriesSpec& spec, const std::string& row) {
  SeriesResult result;
  result.spec = spec;
  std::istringstream words(row);
  std::size_t fields = 0;
  for (std::string word; words >> word;) {
    const auto equals = word.find('=');
    const std::string name = word.substr(0, equals);
    const std::string value = equals == std::string::npos ? "" : word.substr(equals + 1);
    char* end = nullptr;
    const double parsed = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0') throw std::runtime_error("bench row field '" + word + "' is not a number");
    if (name == "fills") {
      result.fills = std::size_t(parsed);
    } else if (name == "failed") {
      result.failed = std::size_t(parsed);
    } else {
      bool known = false;
      for (const Field& field : kFields) {
        if (name == field.name) {
          result.*field.value = parsed;
          known = true;
        }
      }
      if (!known) throw std::runtime_error("bench row has an unknown field '" + name + "'");
    }
    ++fields;
  }
  if (fields != 2 + std::size(kFields)) throw std::runtime_error("bench row '" + row + "' lacks fields");
  return result;
}

}  // namespace dynweigh::tools
