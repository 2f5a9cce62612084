#include "dynweigh/granular/extended_heap_2d.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace dynweigh::granular {

namespace {
constexpr int kWallHeight = std::numeric_limits<int>::max() / 4;
}

ExtendedHeap2d::ExtendedHeap2d(int columns, int critical_step, HeapEdges edges)
    : critical_step_(critical_step),
      edges_(edges),
      heights_(static_cast<std::size_t>(columns), 0),
      queued_stamp_(static_cast<std::size_t>(columns), 0),
      toppled_stamp_(static_cast<std::size_t>(columns), 0) {
  if (columns < 1) throw std::invalid_argument("heap needs at least one column");
  if (critical_step < 1) throw std::invalid_argument("critical step must be at least 1");
  front_.reserve(static_cast<std::size_t>(columns));
  next_front_.reserve(static_cast<std::size_t>(columns));
}

int ExtendedHeap2d::max_height() const { return *std::max_element(heights_.begin(), heights_.end()); }

std::int64_t ExtendedHeap2d::total_grains() const {
  std::int64_t total = 0;
  for (const int h : heights_) total += h;
  return total;
}

int ExtendedHeap2d::neighbour_height(int column) const {
  if (column >= 0 && column < columns()) return heights_[static_cast<std::size_t>(column)];
  return edges_ == HeapEdges::closed_container ? kWallHeight : 0;
}

bool ExtendedHeap2d::is_pit(int column) const {
  if (column < 0 || column >= columns()) return false;
  const int h = heights_[static_cast<std::size_t>(column)];
  return neighbour_height(column - 1) > h && neighbour_height(column + 1) > h;
}

// Lowest neighbour that is lower than `column` by more than the critical step (FTM), or a pit
// lower than `column` (holes first). Returns false when the grain is boxed in.
bool ExtendedHeap2d::steepest_lower_neighbour(int column, Random& random, int& target) const {
  const int here = heights_[static_cast<std::size_t>(column)];
  int best_height = here;
  int candidates[2];
  int count = 0;
  for (const int neighbour : {column - 1, column + 1}) {
    const int h = neighbour_height(neighbour);
    // Staying would leave a step above critical: the grain is not boxed in and moves on.
    const bool free_to_move = here - h >= critical_step_;
    const bool hole = h < here && is_pit(neighbour);
    if (!(free_to_move || hole)) continue;
    if (h < best_height) {
      best_height = h;
      count = 0;
    }
    if (h == best_height) candidates[count++] = neighbour;
  }
  if (count == 0) return false;
  target = count == 1 ? candidates[0] : candidates[random.below(2)];
  return true;
}

int ExtendedHeap2d::roll(int column, Random& random) {
  int target = column;
  while (steepest_lower_neighbour(column, random, target)) {
    ++rolling_moves_;
    if (target < 0 || target >= columns()) return kOutside;  // rolled off the open floor
    column = target;
  }
  return column;
}

Avalanche ExtendedHeap2d::add_grain(int column, Random& random) {
  if (column < 0 || column >= columns()) throw std::out_of_range("grain dropped outside the heap");
  Avalanche avalanche;
  // The grain lands on top of the column and rolls while it is free to move. The resting test
  // uses the height before the grain is added, so the grain settles where it lands.
  // Its run down the slope is the avalanche of this model: one move per wave.
  const std::int64_t moves_before = rolling_moves_;
  const int rest = roll(column, random);
  avalanche.size = rolling_moves_ - moves_before;
  avalanche.duration = avalanche.size;
  avalanche.area = avalanche.size;
  if (rest == kOutside) {
    avalanche.grains_lost = 1;
    return avalanche;
  }
  ++heights_[static_cast<std::size_t>(rest)];

  // A grain resting in a pit or against a wall can still leave a step above critical; the pile
  // then relaxes by eq. 3.2.
  ++avalanche_counter_;
  ++wave_counter_;
  front_.clear();
  auto unstable = [this](int c) {
    const int h = heights_[static_cast<std::size_t>(c)];
    return h - neighbour_height(c - 1) > critical_step_ || h - neighbour_height(c + 1) > critical_step_;
  };
  for (int c = std::max(0, rest - 1); c <= std::min(columns() - 1, rest + 1); ++c) {
    if (unstable(c)) {
      front_.push_back(c);
      queued_stamp_[static_cast<std::size_t>(c)] = wave_counter_;
    }
  }
  while (!front_.empty()) {
    ++avalanche.duration;
    ++wave_counter_;
    next_front_.clear();
    for (const int c : front_) {
      if (!unstable(c)) continue;
      // The top grain tumbles to the lower neighbour (eq. 3.2).
      const int left = neighbour_height(c - 1);
      const int right = neighbour_height(c + 1);
      int to = left < right ? c - 1 : c + 1;
      if (left == right) to = random.below(2) == 0 ? c - 1 : c + 1;
      --heights_[static_cast<std::size_t>(c)];
      ++avalanche.size;
      if (toppled_stamp_[static_cast<std::size_t>(c)] != avalanche_counter_) {
        toppled_stamp_[static_cast<std::size_t>(c)] = avalanche_counter_;
        ++avalanche.area;
      }
      if (to < 0 || to >= columns()) {
        ++avalanche.grains_lost;
      } else {
        ++heights_[static_cast<std::size_t>(to)];
      }
      for (int n = std::max(0, c - 2); n <= std::min(columns() - 1, c + 2); ++n) {
        if (queued_stamp_[static_cast<std::size_t>(n)] != wave_counter_ && unstable(n)) {
          queued_stamp_[static_cast<std::size_t>(n)] = wave_counter_;
          next_front_.push_back(n);
        }
      }
    }
    front_.swap(next_front_);
  }
  return avalanche;
}

}  // namespace dynweigh::granular
