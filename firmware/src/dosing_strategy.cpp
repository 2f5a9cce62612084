#include "dynweigh/firmware/dosing_strategy.hpp"

#include <cstring>

namespace dynweigh::firmware {
namespace {
const char* const kNames[kDosingStrategyCount] = {"model", "preact", "twostage", "learn", "pac", "flowpreact"};
}

const char* strategy_name(DosingStrategy strategy) { return kNames[static_cast<int>(strategy)]; }

bool parse_strategy(const char* name, DosingStrategy& strategy) {
  for (int i = 0; i < kDosingStrategyCount; ++i) {
    if (std::strcmp(name, kNames[i]) == 0) {
      strategy = static_cast<DosingStrategy>(i);
      return true;
    }
  }
  return false;
}

bool strategy_available(DosingStrategy strategy) {
  (void)strategy;
  return true;
}

}  // namespace dynweigh::firmware
