#pragma once
#include <cstdint>

namespace dynweigh::firmware {

// docs/console.md: `dose <grams> [<strategy>]`.
enum class DosingStrategy : std::uint8_t { model = 0, preact = 1, twostage = 2, learn = 3, pac = 4, flowpreact = 5 };
inline constexpr int kDosingStrategyCount = 6;

const char* strategy_name(DosingStrategy strategy);
// False if `name` names no strategy.
bool parse_strategy(const char* name, DosingStrategy& strategy);
// Strategies this build can run (the others are recognised but answered with an error).
bool strategy_available(DosingStrategy strategy);

}  // namespace dynweigh::firmware
