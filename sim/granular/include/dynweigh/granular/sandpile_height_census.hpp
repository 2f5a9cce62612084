#pragma once
// Counts how often each stable height occurs in the interior of a BTW sandpile, to compare with
// the exact stationary probabilities (Majumdar & Dhar 1991: P(0) = 2/pi^2 - 4/pi^3 in 2D).
// Only sites at least `margin` away from every edge are counted, because the open boundary
// lowers the heights next to it.
#include <cstdint>
#include <vector>

#include "dynweigh/granular/btw_sandpile.hpp"

namespace dynweigh::granular {

class SandpileHeightCensus {
 public:
  SandpileHeightCensus(const BtwSandpile& pile, int margin);

  void count(const BtwSandpile& pile);
  std::int64_t samples() const { return samples_; }
  double probability(int height) const;
  double mean_height() const;
  std::size_t counted_sites() const { return sites_.size(); }

 private:
  std::vector<std::size_t> sites_;
  std::vector<std::int64_t> height_counts_;
  std::int64_t samples_ = 0;
};

}  // namespace dynweigh::granular
