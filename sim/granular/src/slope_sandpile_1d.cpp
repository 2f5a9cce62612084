#include "dynweigh/granular/slope_sandpile_1d.hpp"

#include <stdexcept>

namespace dynweigh::granular {

SlopeSandpile1d::SlopeSandpile1d(int columns, int critical_slope)
    : critical_slope_(critical_slope),
      slopes_(static_cast<std::size_t>(columns), 0),
      queued_stamp_(static_cast<std::size_t>(columns), 0),
      toppled_stamp_(static_cast<std::size_t>(columns), 0) {
  if (columns < 1) throw std::invalid_argument("slope sandpile needs at least one column");
  if (critical_slope < 1) throw std::invalid_argument("critical slope must be at least 1");
  front_.reserve(static_cast<std::size_t>(columns));
  next_front_.reserve(static_cast<std::size_t>(columns));
}

int SlopeSandpile1d::height(int column) const {
  int h = 0;
  for (int i = columns() - 1; i >= column; --i) h += slopes_[static_cast<std::size_t>(i)];
  return h;
}

std::vector<int> SlopeSandpile1d::height_profile() const {
  std::vector<int> heights(slopes_.size(), 0);
  int h = 0;
  for (int i = columns() - 1; i >= 0; --i) {
    h += slopes_[static_cast<std::size_t>(i)];
    heights[static_cast<std::size_t>(i)] = h;
  }
  return heights;
}

std::int64_t SlopeSandpile1d::total_grains() const {
  std::int64_t total = 0;
  for (const int h : height_profile()) total += h;
  return total;
}

bool SlopeSandpile1d::is_critical_staircase() const {
  for (const int z : slopes_) {
    if (z != critical_slope_) return false;
  }
  return true;
}

void SlopeSandpile1d::tumble(int column, Avalanche& avalanche) {
  const auto i = static_cast<std::size_t>(column);
  const bool at_edge = column == columns() - 1;
  if (column > 0) slopes_[i - 1] += 1;
  if (at_edge) {
    slopes_[i] -= 1;
    ++avalanche.grains_lost;
  } else {
    slopes_[i] -= 2;
    slopes_[i + 1] += 1;
  }
  ++avalanche.size;
  if (toppled_stamp_[i] != avalanche_counter_) {
    toppled_stamp_[i] = avalanche_counter_;
    ++avalanche.area;
  }
}

Avalanche SlopeSandpile1d::add_grain(int column) {
  if (column < 0 || column >= columns()) throw std::out_of_range("grain added outside the slope model");
  const auto i = static_cast<std::size_t>(column);
  if (column > 0) slopes_[i - 1] -= 1;
  slopes_[i] += 1;

  Avalanche avalanche;
  ++avalanche_counter_;
  front_.clear();
  ++wave_counter_;
  // Adding at i changes z_(i-1) and z_i; only z_i grew.
  if (slopes_[i] > critical_slope_) {
    front_.push_back(column);
    queued_stamp_[i] = wave_counter_;
  }
  while (!front_.empty()) {
    ++avalanche.duration;
    ++wave_counter_;
    next_front_.clear();
    for (const int site : front_) {
      if (slopes_[static_cast<std::size_t>(site)] <= critical_slope_) continue;
      tumble(site, avalanche);
      for (int neighbour = site - 1; neighbour <= site + 1; ++neighbour) {
        if (neighbour < 0 || neighbour >= columns()) continue;
        const auto n = static_cast<std::size_t>(neighbour);
        if (slopes_[n] > critical_slope_ && queued_stamp_[n] != wave_counter_) {
          queued_stamp_[n] = wave_counter_;
          next_front_.push_back(neighbour);
        }
      }
    }
    front_.swap(next_front_);
  }
  return avalanche;
}

}  // namespace dynweigh::granular
