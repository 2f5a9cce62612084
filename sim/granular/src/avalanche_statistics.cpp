#include "dynweigh/granular/avalanche_statistics.hpp"

#include <cmath>
#include <vector>

namespace dynweigh::granular {

namespace {
int log2_bin(std::int64_t size) {
  int bin = 0;
  while (size > 1 && bin < AvalancheStatistics::kSizeBins - 1) {
    size >>= 1;
    ++bin;
  }
  return bin;
}
}  // namespace

void AvalancheStatistics::record(const Avalanche& avalanche) {
  ++grains_;
  if (!avalanche.happened()) return;
  ++avalanches_;
  size_sum_ += static_cast<double>(avalanche.size);
  area_sum_ += static_cast<double>(avalanche.area);
  duration_sum_ += static_cast<double>(avalanche.duration);
  if (avalanche.size > largest_size_) largest_size_ = avalanche.size;
  ++size_histogram_[static_cast<std::size_t>(log2_bin(avalanche.size))];
}

double AvalancheStatistics::mean_topplings_per_grain() const {
  return grains_ > 0 ? size_sum_ / static_cast<double>(grains_) : 0.0;
}
double AvalancheStatistics::mean_size() const {
  return avalanches_ > 0 ? size_sum_ / static_cast<double>(avalanches_) : 0.0;
}
double AvalancheStatistics::mean_area() const {
  return avalanches_ > 0 ? area_sum_ / static_cast<double>(avalanches_) : 0.0;
}
double AvalancheStatistics::mean_duration() const {
  return avalanches_ > 0 ? duration_sum_ / static_cast<double>(avalanches_) : 0.0;
}

double AvalancheStatistics::estimate_tau_s(std::int64_t min_size, std::int64_t max_size) const {
  // Density in a log bin is count / bin width; fit log(density) = a - tau * log(size).
  std::vector<double> xs, ys;
  for (int bin = 0; bin < kSizeBins; ++bin) {
    const double low = std::ldexp(1.0, bin);
    const double high = std::ldexp(1.0, bin + 1);
    if (low < static_cast<double>(min_size) || high > 2.0 * static_cast<double>(max_size)) continue;
    const std::int64_t count = size_histogram_[static_cast<std::size_t>(bin)];
    if (count < 10) continue;
    xs.push_back(std::log(std::sqrt(low * high)));
    ys.push_back(std::log(static_cast<double>(count) / (high - low)));
  }
  if (xs.size() < 3) return 0.0;
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    mx += xs[i];
    my += ys[i];
  }
  mx /= static_cast<double>(xs.size());
  my /= static_cast<double>(xs.size());
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    sxy += (xs[i] - mx) * (ys[i] - my);
    sxx += (xs[i] - mx) * (xs[i] - mx);
  }
  return sxx > 0 ? -sxy / sxx : 0.0;
}

}  // namespace dynweigh::granular
