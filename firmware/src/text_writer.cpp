#include "dynweigh/firmware/text_writer.hpp"

#include <cmath>
#include <cstring>
#include <limits>

namespace dynweigh::firmware {
namespace {

// |value| * scale rounded half away from zero, in integers (the M4F has no double): a float is an
// integer mantissa times a power of two, so the product is exact before the one rounding.
std::int64_t scaled_magnitude(float value, std::int64_t scale) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  const std::uint32_t biased_exponent = (bits >> 23) & 0xFFu;
  std::uint64_t mantissa = bits & 0x7FFFFFu;
  int exponent = -149;  // subnormal
  if (biased_exponent != 0) {
    mantissa |= 0x800000u;
    exponent = int(biased_exponent) - 150;
  }
  const std::uint64_t product = mantissa * std::uint64_t(scale);
  constexpr std::uint64_t kMax = std::uint64_t(std::numeric_limits<std::int64_t>::max());
  if (exponent >= 0) {
    if (exponent >= 40 || product > (kMax >> exponent)) return std::int64_t(kMax);
    return std::int64_t(product << exponent);
  }
  if (exponent < -62) return 0;  // below half of one unit
  const int shift = -exponent;
  return std::int64_t((product + (std::uint64_t(1) << (shift - 1))) >> shift);
}

}  // namespace

void TextWriter::put(char c) {
  if (size_ == kCapacity) return;  // callers check free_space() before an answer; never block
  ring_[(head_ + size_) % kCapacity] = c;
  ++size_;
}

void TextWriter::write(const char* text) {
  while (*text) put(*text++);
}

void TextWriter::write_int(std::int64_t value) {
  char digits[24];
  std::size_t n = 0;
  const bool negative = value < 0;
  std::uint64_t magnitude = negative ? std::uint64_t(0) - std::uint64_t(value) : std::uint64_t(value);
  do {
    digits[n++] = char('0' + magnitude % 10);
    magnitude /= 10;
  } while (magnitude);
  if (negative) put('-');
  while (n) put(digits[--n]);
}

void TextWriter::write_decimal(float value, int max_decimals) {
  std::int64_t scale = 1;
  for (int i = 0; i < max_decimals; ++i) scale *= 10;
  const std::int64_t fixed = scaled_magnitude(value, scale);
  if (std::signbit(value) && fixed != 0) put('-');
  write_int(fixed / scale);
  std::int64_t fraction = fixed % scale;
  int decimals = max_decimals;
  while (decimals > 0 && fraction % 10 == 0) {
    fraction /= 10;
    --decimals;
  }
  if (decimals == 0) return;
  put('.');
  std::int64_t divisor = 1;
  for (int i = 1; i < decimals; ++i) divisor *= 10;
  for (; divisor > 0; divisor /= 10) put(char('0' + (fraction / divisor) % 10));
}

std::size_t TextWriter::drain(char* destination, std::size_t capacity) {
  std::size_t n = 0;
  while (n < capacity && size_ > 0) {
    destination[n++] = ring_[head_];
    head_ = (head_ + 1) % kCapacity;
    --size_;
  }
  return n;
}

}  // namespace dynweigh::firmware
