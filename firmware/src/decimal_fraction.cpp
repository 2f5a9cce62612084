#include "dynweigh/firmware/decimal_fraction.hpp"

#include <cmath>

namespace dynweigh::firmware {

float nearest_float(std::uint64_t numerator, int decimals, bool more_digits) {
  std::uint64_t denominator = 1;
  for (int i = 0; i < decimals; ++i) denominator *= 10;
  std::uint64_t quotient = numerator / denominator;
  std::uint64_t remainder = numerator % denominator;
  if (quotient == 0 && remainder == 0) return 0.0f;
  // Long division, one binary digit at a time, until the quotient has a float's 24 bits and two more.
  int exponent = 0;
  while (quotient < (std::uint64_t(1) << 26)) {
    remainder <<= 1;
    quotient <<= 1;
    if (remainder >= denominator) {
      remainder -= denominator;
      quotient |= 1;
    }
    --exponent;
  }
  int shift = 0;
  while ((quotient >> shift) >= (std::uint64_t(1) << 24)) ++shift;
  const std::uint64_t half = std::uint64_t(1) << (shift - 1);
  const std::uint64_t dropped = quotient & ((half << 1) - 1);
  const bool beyond = remainder != 0 || more_digits;
  std::uint64_t mantissa = quotient >> shift;
  if (dropped > half || (dropped == half && (beyond || (mantissa & 1)))) ++mantissa;
  return std::ldexp(float(mantissa), exponent + shift);
}

}  // namespace dynweigh::firmware
