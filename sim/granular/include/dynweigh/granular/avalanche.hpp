#pragma once
// One avalanche of a sandpile model: what the statistics and the force signal are built from.
#include <cstdint>

namespace dynweigh::granular {

struct Avalanche {
  std::int64_t size = 0;      // number of topplings (a site toppling n times counts n)
  std::int64_t area = 0;      // number of distinct sites that toppled at least once
  std::int64_t duration = 0;  // number of parallel update waves (0 when nothing toppled)
  std::int64_t grains_lost = 0;  // grains that left the pile over the open boundary
  bool happened() const { return size > 0; }
};

}  // namespace dynweigh::granular
