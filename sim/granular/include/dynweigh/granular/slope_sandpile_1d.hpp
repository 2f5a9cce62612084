#pragma once
// The one-dimensional slope model of the thesis, eqs. 3.1-3.2 (BTW 1987, Kadanoff et al. 1989).
// Column 0 stands against a closed wall (the axis of a symmetric pile, where the thesis adds its
// grains); past the last column the floor is open and grains leave. The state is the slope
// z_i = h_i - h_(i+1) with h_columns = 0.
//   adding a grain at i:     z_(i-1) -= 1, z_i += 1                       (eq. 3.1)
//   z_i > z_c, one grain tumbles:  z_(i-1) += 1, z_i -= 2, z_(i+1) += 1  (eq. 3.2)
// At the wall the (i-1) term is absent; at the open edge the grain leaves, so z_last -= 1 only.
// The model settles into the critical staircase, every slope at z_c, through which each further
// grain added at the wall passes to the edge.
#include <cstdint>
#include <vector>

#include "dynweigh/granular/avalanche.hpp"

namespace dynweigh::granular {

class SlopeSandpile1d {
 public:
  SlopeSandpile1d(int columns, int critical_slope);

  int columns() const { return static_cast<int>(slopes_.size()); }
  int critical_slope() const { return critical_slope_; }
  int slope(int column) const { return slopes_[static_cast<std::size_t>(column)]; }
  int height(int column) const;  // h_i = sum of slopes from i to the edge
  std::vector<int> height_profile() const;
  std::int64_t total_grains() const;
  bool is_critical_staircase() const;

  // Adds one grain at `column` (eq. 3.1) and relaxes in parallel waves (eq. 3.2).
  Avalanche add_grain(int column);

 private:
  void tumble(int column, Avalanche& avalanche);

  int critical_slope_;
  std::vector<int> slopes_;
  std::vector<std::uint32_t> queued_stamp_;
  std::vector<std::uint32_t> toppled_stamp_;
  std::vector<int> front_, next_front_;
  std::uint32_t wave_counter_ = 0;
  std::uint32_t avalanche_counter_ = 0;
};

}  // namespace dynweigh::granular
