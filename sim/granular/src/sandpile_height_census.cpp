#include "dynweigh/granular/sandpile_height_census.hpp"

#include <stdexcept>

namespace dynweigh::granular {

SandpileHeightCensus::SandpileHeightCensus(const BtwSandpile& pile, int margin)
    : height_counts_(static_cast<std::size_t>(pile.critical_height()), 0) {
  const int side = pile.side_length();
  if (2 * margin >= side) throw std::invalid_argument("census margin leaves no interior sites");
  const int dim = pile.dimension();
  const int low = margin;
  const int high = side - margin;
  for (int z = (dim >= 3 ? low : 0); z < (dim >= 3 ? high : 1); ++z) {
    for (int y = (dim >= 2 ? low : 0); y < (dim >= 2 ? high : 1); ++y) {
      for (int x = low; x < high; ++x) sites_.push_back(pile.site_at(x, y, z));
    }
  }
}

void SandpileHeightCensus::count(const BtwSandpile& pile) {
  for (const std::size_t site : sites_) {
    const int h = pile.height(site);
    if (h >= 0 && h < static_cast<int>(height_counts_.size())) ++height_counts_[static_cast<std::size_t>(h)];
  }
  ++samples_;
}

double SandpileHeightCensus::probability(int height) const {
  std::int64_t total = 0;
  for (const std::int64_t c : height_counts_) total += c;
  if (total == 0 || height < 0 || height >= static_cast<int>(height_counts_.size())) return 0.0;
  return static_cast<double>(height_counts_[static_cast<std::size_t>(height)]) / static_cast<double>(total);
}

double SandpileHeightCensus::mean_height() const {
  std::int64_t total = 0;
  double weighted = 0;
  for (std::size_t h = 0; h < height_counts_.size(); ++h) {
    total += height_counts_[h];
    weighted += static_cast<double>(h) * static_cast<double>(height_counts_[h]);
  }
  return total > 0 ? weighted / static_cast<double>(total) : 0.0;
}

}  // namespace dynweigh::granular
