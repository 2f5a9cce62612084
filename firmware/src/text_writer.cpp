#include "dynweigh/firmware/text_writer.hpp"

namespace dynweigh::firmware {

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
  const double scaled = double(value) * double(scale);
  std::int64_t fixed = std::int64_t(scaled < 0 ? scaled - 0.5 : scaled + 0.5);
  if (fixed < 0) {
    put('-');
    fixed = -fixed;
  }
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
