#include "replay_source.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace dynweigh::tools {
namespace {

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, separator)) fields.push_back(field);
  return fields;
}

bool parse_long(const std::string& text, long& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtol(text.c_str(), &end, 10);
  return end && *end == '\0';
}

bool parse_raw(const std::string& text, std::int32_t& value) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || !end || *end != '\0') return false;
  value = std::int32_t(v < 0 ? v - 0.5 : v + 0.5);
  return true;
}

}  // namespace

std::vector<std::int32_t> load_replay_samples(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read replay file " + path);
  std::vector<std::int32_t> samples;
  std::string line;
  int raw_column = -1;
  bool first = true;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (first && line.find(',') != std::string::npos) {  // a CSV: find the raw column
      const auto header = split(line, ',');
      for (std::size_t i = 0; i < header.size(); ++i) {
        if (header[i] == "raw") raw_column = int(i);
      }
      if (raw_column < 0) throw std::runtime_error("replay CSV " + path + " has no 'raw' column");
      first = false;
      continue;
    }
    first = false;
    if (raw_column >= 0) {
      const auto fields = split(line, ',');
      std::int32_t raw = 0;
      if (std::size_t(raw_column) < fields.size() && parse_raw(fields[std::size_t(raw_column)], raw)) {
        samples.push_back(raw);
      }
      continue;
    }
    // readtestdata: exactly four integers; anything else (OK, prompts, RESULT lines) is skipped.
    std::istringstream words(line);
    std::string word[5];
    int count = 0;
    while (count < 5 && words >> word[count]) ++count;
    long values[4];
    if (count != 4) continue;
    bool ok = true;
    for (int i = 0; i < 4; ++i) ok = ok && parse_long(word[i], values[i]);
    if (ok) samples.push_back(std::int32_t(values[1]));
  }
  if (samples.empty()) throw std::runtime_error("replay file " + path + " holds no samples");
  return samples;
}

}  // namespace dynweigh::tools
