#include "dynweigh/granular/cell_grid.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dynweigh::granular {

void CellGrid::configure(double min_x, double min_y, double max_x, double max_y, double cell_size, std::size_t capacity) {
  if (!(cell_size > 0) || !(max_x > min_x) || !(max_y > min_y)) throw std::invalid_argument("bad cell grid");
  min_x_ = min_x;
  min_y_ = min_y;
  inv_cell_ = 1.0 / cell_size;
  cells_x_ = std::max(1, static_cast<int>(std::floor((max_x - min_x) / cell_size)));
  cells_y_ = std::max(1, static_cast<int>(std::floor((max_y - min_y) / cell_size)));
  start_.assign(static_cast<std::size_t>(cells_x_) * static_cast<std::size_t>(cells_y_) + 1, 0);
  items_.assign(capacity, 0);
  cell_of_.assign(capacity, 0);
}

int CellGrid::cell_x_of(double x) const {
  const int c = static_cast<int>(std::floor((x - min_x_) * inv_cell_));
  return std::min(std::max(c, 0), cells_x_ - 1);
}

int CellGrid::cell_y_of(double y) const {
  const int c = static_cast<int>(std::floor((y - min_y_) * inv_cell_));
  return std::min(std::max(c, 0), cells_y_ - 1);
}

void CellGrid::build(const double* x, const double* y, std::size_t count) {
  std::fill(start_.begin(), start_.end(), 0u);
  for (std::size_t i = 0; i < count; ++i) {
    const auto cell = static_cast<std::uint32_t>(cell_y_of(y[i]) * cells_x_ + cell_x_of(x[i]));
    cell_of_[i] = cell;
    ++start_[cell + 1];
  }
  for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
  // Fill in index order so each cell lists its items ascending (a deterministic pair order).
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t cell = cell_of_[i];
    items_[start_[cell]++] = static_cast<std::uint32_t>(i);
  }
  for (std::size_t c = start_.size() - 1; c > 0; --c) start_[c] = start_[c - 1];
  start_[0] = 0;
}

}  // namespace dynweigh::granular
