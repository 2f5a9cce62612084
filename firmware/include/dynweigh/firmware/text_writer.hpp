#pragma once
// The console's transmit ring. Commands write whole answers into it; the board drains it at the
// pace of its line (UART baud, pty, stdout). Nothing here blocks or allocates.
#include <cstddef>
#include <cstdint>

namespace dynweigh::firmware {

class TextWriter {
 public:
  static constexpr std::size_t kCapacity = 4096;

  std::size_t free_space() const { return kCapacity - size_; }
  std::size_t size() const { return size_; }

  void put(char c);
  void write(const char* text);
  void write_int(std::int64_t value);
  void write_decimal(float value, int max_decimals);  // trailing zeros trimmed
  void line(const char* text) { write(text); put('\n'); }

  std::size_t drain(char* destination, std::size_t capacity);

 private:
  char ring_[kCapacity] = {};
  std::size_t head_ = 0;  // next byte to drain
  std::size_t size_ = 0;
};

}  // namespace dynweigh::firmware
