#pragma once
// The Bak-Tang-Wiesenfeld (Abelian) sandpile on a d-dimensional hypercubic lattice, d = 1, 2, 3
// (thesis section 3.2; Bak, Tang & Wiesenfeld 1987; Dhar 1990).
// Heights 0 .. 2d-1 are stable; a site with height >= z_c = 2d topples, giving one grain to each
// of its 2d neighbours. Boundaries are open: grains toppled across the edge are lost.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "dynweigh/granular/avalanche.hpp"
#include "dynweigh/granular/random.hpp"

namespace dynweigh::granular {

// The order in which unstable sites are toppled. The Abelian property says the final state and
// the number of topplings of each site do not depend on it; the tests check that claim.
enum class ToppleOrder {
  parallel_waves,     // all sites unstable at the start of a wave topple in that wave
  last_in_first_out,  // depth first
  random_pick,        // an unstable site drawn at random each time
};

class BtwSandpile {
 public:
  BtwSandpile(int dimension, int side_length);

  int dimension() const { return dimension_; }
  int side_length() const { return side_length_; }
  int critical_height() const { return 2 * dimension_; }
  std::size_t site_count() const { return interior_to_padded_.size(); }

  // Sites are numbered 0 .. site_count()-1, first coordinate fastest.
  std::size_t site_at(int x, int y = 0, int z = 0) const;
  std::size_t centre_site() const;
  int height(std::size_t site) const { return heights_[interior_to_padded_[site]]; }
  // Sets a height directly (may be unstable; relax() then settles it). For initial states.
  void set_height(std::size_t site, int height) { heights_[interior_to_padded_[site]] = height; }
  void fill(int height);
  // How often each site has toppled since construction (the odometer of the Abelian group).
  std::int64_t topplings_of(std::size_t site) const { return odometer_[interior_to_padded_[site]]; }
  std::int64_t total_grains() const;

  // Adds one grain and relaxes by parallel waves; returns the avalanche it caused.
  Avalanche add_grain(std::size_t site);
  Avalanche add_random_grain(Random& random) {
    return add_grain(static_cast<std::size_t>(random.below(site_count())));
  }
  // Relaxes every unstable site in the given order; random_pick uses `random`.
  Avalanche relax(ToppleOrder order, Random* random = nullptr);

 private:
  void topple(std::size_t padded_site, Avalanche& avalanche);
  Avalanche relax_in_waves();
  Avalanche relax_one_at_a_time(ToppleOrder order, Random* random);
  void reset_sinks();

  int dimension_;
  int side_length_;
  int critical_height_;
  std::vector<std::ptrdiff_t> neighbour_offsets_;
  // Padded lattice: a one-site frame of sinks around the interior. A sink starts very negative
  // so it can never topple; grains lost to it are counted from sink_neighbours_.
  std::vector<std::int32_t> heights_;
  std::vector<std::uint8_t> sink_neighbours_;
  std::vector<std::int64_t> odometer_;
  std::vector<std::uint32_t> queued_stamp_;   // wave in which a site was last queued
  std::vector<std::uint32_t> toppled_stamp_;  // avalanche in which a site last toppled
  std::vector<std::uint32_t> interior_to_padded_;
  std::vector<std::uint32_t> front_, next_front_;
  std::uint32_t wave_counter_ = 0;
  std::uint32_t avalanche_counter_ = 0;
  std::int64_t grains_since_sink_reset_ = 0;
};

}  // namespace dynweigh::granular
