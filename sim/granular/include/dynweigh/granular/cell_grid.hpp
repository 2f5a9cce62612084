#pragma once
// Uniform cell list for contact search (the thesis' occupied cells, section 3.4): cells at least
// one interaction range wide, so a disc's partners are in its own or the 8 surrounding cells and
// the search is O(N). Built by a counting sort into preallocated arrays: no allocation after
// set-up. Points outside the domain are clamped into the border cells (still correct, slower).
#include <cstdint>
#include <vector>

namespace dynweigh::granular {

class CellGrid {
 public:
  void configure(double min_x, double min_y, double max_x, double max_y, double cell_size, std::size_t capacity);
  void build(const double* x, const double* y, std::size_t count);

  int cells_x() const { return cells_x_; }
  int cells_y() const { return cells_y_; }
  int cell_x_of(double x) const;
  int cell_y_of(double y) const;
  // Items of cell (cx, cy): item indices [begin, end) of items().
  std::uint32_t begin(int cx, int cy) const { return start_[static_cast<std::size_t>(cy * cells_x_ + cx)]; }
  std::uint32_t end(int cx, int cy) const { return start_[static_cast<std::size_t>(cy * cells_x_ + cx) + 1]; }
  const std::uint32_t* items() const { return items_.data(); }
  std::uint32_t cell_of(std::size_t item) const { return cell_of_[item]; }

 private:
  double min_x_ = 0, min_y_ = 0, inv_cell_ = 1;
  int cells_x_ = 1, cells_y_ = 1;
  std::vector<std::uint32_t> start_;
  std::vector<std::uint32_t> items_;
  std::vector<std::uint32_t> cell_of_;
};

}  // namespace dynweigh::granular
