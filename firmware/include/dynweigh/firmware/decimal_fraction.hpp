#pragma once
// A decimal number typed on the console, as the float nearest to it, in integer arithmetic: the
// M4F has no double, and a float sum of the digits would round at every digit.
#include <cstdint>

namespace dynweigh::firmware {

// The float nearest to numerator / 10^decimals (ties to even); `more_digits`: non-zero digits were
// dropped after the numerator's last (the value is a little above it). decimals <= 18.
float nearest_float(std::uint64_t numerator, int decimals, bool more_digits);

}  // namespace dynweigh::firmware
