#include "family_comparison.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <utility>

namespace dynweigh::tools {
namespace {

constexpr double kAskedClass = 1.0;

// The value of ` key=` (or of the line's first field) up to the next space; empty if absent.
std::string field(const std::string& line, const std::string& key) {
  const std::string prefix = key + "=";
  std::size_t start = prefix.size();
  if (line.compare(0, prefix.size(), prefix) != 0) {
    const std::size_t at = line.find(" " + prefix);
    if (at == std::string::npos) return {};
    start = at + 1 + prefix.size();
  }
  const std::size_t end = line.find(' ', start);
  return line.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

// X(x) as x; no class at all as worse than any.
double steady_class(const std::string& line) {
  const std::string text = field(line, "class_steady");
  if (text.size() < 4 || text.compare(0, 2, "X(") != 0) return INFINITY;
  return std::strtod(text.c_str() + 2, nullptr);
}

struct Entry {
  double steady_class = INFINITY;
  double time_ratio = INFINITY;
};

bool faster_than_all(const Entry& model, const std::map<std::string, Entry>& baselines, double floor) {
  for (const auto& [name, b] : baselines) {
    (void)name;
    const double model_class = std::fmax(model.steady_class, floor), baseline_class = std::fmax(b.steady_class, floor);
    if (!(model_class <= baseline_class && model.time_ratio < b.time_ratio)) return false;
  }
  return true;
}

// The model reached a class, and no baseline at an equal or better one took at most its time.
bool undominated(const Entry& model, const std::map<std::string, Entry>& baselines) {
  if (!std::isfinite(model.steady_class)) return false;
  for (const auto& [name, b] : baselines) {
    (void)name;
    if (b.steady_class <= model.steady_class && b.time_ratio <= model.time_ratio) return false;
  }
  return true;
}

}  // namespace

bool is_family_baseline(const std::string& strategy) {
  return strategy != "model" && strategy != "learn" && strategy != "oracle" && strategy != "oracle-scale";
}

std::optional<std::string> family_comparison_summary(const std::vector<std::string>& cell_lines) {
  // cell (plant, target) -> strategy -> its steady class and time
  std::map<std::pair<std::string, std::string>, std::map<std::string, Entry>> cells;
  std::map<std::string, bool> baselines;
  for (const std::string& line : cell_lines) {
    const std::string strategy = field(line, "strategy");
    if (strategy.empty()) continue;
    Entry e;
    e.steady_class = steady_class(line);
    const std::string time = field(line, "time_ratio");
    // A cell none of whose fills was timed (every one failed) shows 0: it was not fast.
    const double ratio = time.empty() ? 0.0 : std::strtod(time.c_str(), nullptr);
    e.time_ratio = ratio > 0.0 ? ratio : INFINITY;
    cells[{field(line, "plant"), field(line, "target_g")}][strategy] = e;
    if (is_family_baseline(strategy)) baselines[strategy] = true;
  }
  if (baselines.empty()) return std::nullopt;
  std::size_t compared = 0, faster = 0, faster_x1 = 0, unbeaten = 0;
  for (const auto& [cell, strategies] : cells) {
    (void)cell;
    const auto model = strategies.find("model");
    if (model == strategies.end()) continue;
    std::map<std::string, Entry> met;
    for (const auto& [name, entry] : strategies) {
      if (is_family_baseline(name)) met[name] = entry;
    }
    if (met.empty()) continue;
    ++compared;
    faster += faster_than_all(model->second, met, 0.0);
    faster_x1 += faster_than_all(model->second, met, kAskedClass);
    unbeaten += undominated(model->second, met);
  }
  if (compared == 0) return std::nullopt;
  std::string names;
  for (const auto& [name, present] : baselines) {
    (void)present;
    names += (names.empty() ? "" : ",") + name;
  }
  const double n = double(compared);
  char numbers[240];
  std::snprintf(numbers, sizeof numbers,
                " cells=%zu faster_cells=%zu faster_share=%.3f faster_cells_x1=%zu faster_share_x1=%.3f"
                " unbeaten_cells=%zu unbeaten_share=%.3f",
                compared, faster, double(faster) / n, faster_x1, double(faster_x1) / n, unbeaten, double(unbeaten) / n);
  return "summary comparison=model baselines=" + names + numbers;
}

}  // namespace dynweigh::tools
