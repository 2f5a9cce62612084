#pragma once
// The thesis' extended 2D granular heap (section 3.2, fig. 3.3C): a vertical cross-section in
// which one pixel is one unit of grain, so the state is the height of each column.
// A dropped grain falls down its column onto the heap. It is free to move (FTM), not boxed in,
// while staying would leave a step to a neighbouring column above the critical step; it then
// rolls to the lowest such neighbour. Holes are filled first: a neighbouring one-column pit
// (lower than both its neighbours) below the grain takes the grain whatever the step. The run of
// the grain is this model's avalanche (size = duration = moves). Should a step above critical
// remain, the pile relaxes by the toppling rule of eq. 3.2, which adds to the same avalanche.
#include <cstdint>
#include <vector>

#include "dynweigh/granular/avalanche.hpp"
#include "dynweigh/granular/random.hpp"

namespace dynweigh::granular {

enum class HeapEdges {
  closed_container,  // walls at both ends: nothing leaves, the heap fills the container
  open_floor,        // the floor ends past both edge columns: grains rolling off are lost
};

class ExtendedHeap2d {
 public:
  ExtendedHeap2d(int columns, int critical_step, HeapEdges edges);

  int columns() const { return static_cast<int>(heights_.size()); }
  int centre_column() const { return columns() / 2; }
  int critical_step() const { return critical_step_; }
  const std::vector<int>& heights() const { return heights_; }
  int max_height() const;
  std::int64_t total_grains() const;
  std::int64_t rolling_moves() const { return rolling_moves_; }  // cumulative FTM moves

  // Drops one grain on `column`; ties between equally low neighbours are broken by `random`.
  Avalanche add_grain(int column, Random& random);

 private:
  static constexpr int kOutside = -1;
  int neighbour_height(int column) const;  // height of a neighbour, walls very high, open edge 0
  bool is_pit(int column) const;
  int roll(int column, Random& random);
  bool steepest_lower_neighbour(int column, Random& random, int& target) const;

  int critical_step_;
  HeapEdges edges_;
  std::vector<int> heights_;
  std::vector<std::uint32_t> queued_stamp_;
  std::vector<std::uint32_t> toppled_stamp_;
  std::vector<int> front_, next_front_;
  std::uint32_t wave_counter_ = 0;
  std::uint32_t avalanche_counter_ = 0;
  std::int64_t rolling_moves_ = 0;
};

}  // namespace dynweigh::granular
