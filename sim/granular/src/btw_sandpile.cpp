#include "dynweigh/granular/btw_sandpile.hpp"

#include <algorithm>
#include <stdexcept>

namespace dynweigh::granular {

namespace {
// A sink starts this low so that no number of grains a run can deliver makes it topple;
// add_grain() resets sinks long before they could climb back (see kSinkResetInterval).
constexpr std::int32_t kSinkHeight = -(1 << 30);
constexpr std::int64_t kSinkResetInterval = 1 << 20;
}  // namespace

BtwSandpile::BtwSandpile(int dimension, int side_length)
    : dimension_(dimension), side_length_(side_length), critical_height_(2 * dimension) {
  if (dimension < 1 || dimension > 3) throw std::invalid_argument("sandpile dimension must be 1, 2 or 3");
  if (side_length < 1) throw std::invalid_argument("sandpile side length must be positive");
  const std::size_t padded_side = static_cast<std::size_t>(side_length) + 2;
  std::size_t padded_count = 1;
  std::size_t interior_count = 1;
  for (int d = 0; d < dimension; ++d) {
    padded_count *= padded_side;
    interior_count *= static_cast<std::size_t>(side_length);
  }
  if (padded_count > (std::size_t{1} << 31)) throw std::invalid_argument("sandpile lattice too large");
  std::ptrdiff_t stride = 1;
  for (int d = 0; d < dimension; ++d) {
    neighbour_offsets_.push_back(stride);
    neighbour_offsets_.push_back(-stride);
    stride *= static_cast<std::ptrdiff_t>(padded_side);
  }
  heights_.assign(padded_count, kSinkHeight);
  sink_neighbours_.assign(padded_count, 0);
  odometer_.assign(padded_count, 0);
  queued_stamp_.assign(padded_count, 0);
  toppled_stamp_.assign(padded_count, 0);
  interior_to_padded_.reserve(interior_count);
  for (std::size_t index = 0; index < interior_count; ++index) {
    std::size_t rest = index;
    std::size_t padded = 0;
    std::size_t padded_stride = 1;
    for (int d = 0; d < dimension; ++d) {
      const std::size_t coordinate = rest % static_cast<std::size_t>(side_length);
      rest /= static_cast<std::size_t>(side_length);
      padded += (coordinate + 1) * padded_stride;
      padded_stride *= padded_side;
    }
    interior_to_padded_.push_back(static_cast<std::uint32_t>(padded));
  }
  for (const std::uint32_t padded : interior_to_padded_) {
    heights_[padded] = 0;
  }
  for (const std::uint32_t padded : interior_to_padded_) {
    std::uint8_t sinks = 0;
    for (const std::ptrdiff_t offset : neighbour_offsets_) {
      if (heights_[static_cast<std::size_t>(static_cast<std::ptrdiff_t>(padded) + offset)] == kSinkHeight) ++sinks;
    }
    sink_neighbours_[padded] = sinks;
  }
  front_.reserve(interior_count);
  next_front_.reserve(interior_count);
}

std::size_t BtwSandpile::site_at(int x, int y, int z) const {
  const auto side = static_cast<std::size_t>(side_length_);
  std::size_t site = static_cast<std::size_t>(x);
  if (dimension_ >= 2) site += side * static_cast<std::size_t>(y);
  if (dimension_ >= 3) site += side * side * static_cast<std::size_t>(z);
  return site;
}

std::size_t BtwSandpile::centre_site() const {
  const int middle = side_length_ / 2;
  return site_at(middle, middle, middle);
}

void BtwSandpile::fill(int height) {
  for (const std::uint32_t padded : interior_to_padded_) heights_[padded] = height;
}

std::int64_t BtwSandpile::total_grains() const {
  std::int64_t total = 0;
  for (const std::uint32_t padded : interior_to_padded_) total += heights_[padded];
  return total;
}

void BtwSandpile::reset_sinks() {
  // Sinks absorbed grains since the last reset; put them back at the bottom.
  for (std::size_t i = 0; i < heights_.size(); ++i) {
    if (heights_[i] < -(1 << 29)) heights_[i] = kSinkHeight;
  }
}

// Topples a site as often as its height allows (n = h / z_c at once is the same as n single
// topplings in a row, by the Abelian property, and saves queue traffic).
inline void BtwSandpile::topple(std::size_t padded_site, Avalanche& avalanche) {
  const std::int32_t times = heights_[padded_site] / critical_height_;
  heights_[padded_site] -= times * critical_height_;
  odometer_[padded_site] += times;
  avalanche.size += times;
  avalanche.grains_lost += static_cast<std::int64_t>(times) * sink_neighbours_[padded_site];
  if (toppled_stamp_[padded_site] != avalanche_counter_) {
    toppled_stamp_[padded_site] = avalanche_counter_;
    ++avalanche.area;
  }
  for (const std::ptrdiff_t offset : neighbour_offsets_) {
    heights_[static_cast<std::size_t>(static_cast<std::ptrdiff_t>(padded_site) + offset)] += times;
  }
}

Avalanche BtwSandpile::add_grain(std::size_t site) {
  const std::uint32_t padded = interior_to_padded_[site];
  ++heights_[padded];
  if (++grains_since_sink_reset_ >= kSinkResetInterval) {
    reset_sinks();
    grains_since_sink_reset_ = 0;
  }
  if (heights_[padded] < critical_height_) return Avalanche{};
  return relax_in_waves();
}

Avalanche BtwSandpile::relax(ToppleOrder order, Random* random) {
  if (order == ToppleOrder::parallel_waves) return relax_in_waves();
  if (order == ToppleOrder::random_pick && random == nullptr) {
    throw std::invalid_argument("random topple order needs a random generator");
  }
  return relax_one_at_a_time(order, random);
}

Avalanche BtwSandpile::relax_in_waves() {
  Avalanche avalanche;
  ++avalanche_counter_;
  front_.clear();
  ++wave_counter_;
  for (const std::uint32_t padded : interior_to_padded_) {
    if (heights_[padded] >= critical_height_) {
      front_.push_back(padded);
      queued_stamp_[padded] = wave_counter_;
    }
  }
  while (!front_.empty()) {
    ++avalanche.duration;
    ++wave_counter_;
    next_front_.clear();
    for (const std::uint32_t site : front_) {
      if (heights_[site] < critical_height_) continue;
      topple(site, avalanche);
      for (const std::ptrdiff_t offset : neighbour_offsets_) {
        const auto neighbour = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(site) + offset);
        if (heights_[neighbour] >= critical_height_ && queued_stamp_[neighbour] != wave_counter_) {
          queued_stamp_[neighbour] = wave_counter_;
          next_front_.push_back(static_cast<std::uint32_t>(neighbour));
        }
      }
    }
    front_.swap(next_front_);
  }
  return avalanche;
}

Avalanche BtwSandpile::relax_one_at_a_time(ToppleOrder order, Random* random) {
  Avalanche avalanche;
  ++avalanche_counter_;
  ++wave_counter_;  // queued_stamp_ == wave_counter_ marks "in the pending set"
  std::vector<std::uint32_t>& pending = front_;
  pending.clear();
  for (const std::uint32_t padded : interior_to_padded_) {
    if (heights_[padded] >= critical_height_) {
      pending.push_back(padded);
      queued_stamp_[padded] = wave_counter_;
    }
  }
  while (!pending.empty()) {
    std::size_t pick = pending.size() - 1;
    if (order == ToppleOrder::random_pick) pick = static_cast<std::size_t>(random->below(pending.size()));
    const std::uint32_t site = pending[pick];
    pending[pick] = pending.back();
    pending.pop_back();
    queued_stamp_[site] = 0;
    topple(site, avalanche);
    for (const std::ptrdiff_t offset : neighbour_offsets_) {
      const auto neighbour = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(site) + offset);
      if (heights_[neighbour] >= critical_height_ && queued_stamp_[neighbour] != wave_counter_) {
        queued_stamp_[neighbour] = wave_counter_;
        pending.push_back(static_cast<std::uint32_t>(neighbour));
      }
    }
  }
  // One-at-a-time relaxation has no notion of simultaneous waves.
  avalanche.duration = avalanche.size > 0 ? avalanche.size : 0;
  return avalanche;
}

}  // namespace dynweigh::granular
