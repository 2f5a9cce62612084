#pragma once
// Assembles console lines: a line ends at CR, LF or CR LF, empty lines are ignored, and a line
// longer than 80 characters is discarded whole (SPEC §3) and reported once at its end. A line of
// only spaces and tabs is empty too, and NUL bytes (a UART break, terminal padding) are dropped,
// so every line the reader completes is a command the indicator answers exactly once.
#include <cstddef>

namespace dynweigh::firmware {

class ConsoleLineReader {
 public:
  static constexpr std::size_t kMaxLine = 80;

  enum class Event { none, line, too_long };
  // Feeds one byte; on Event::line, line() holds the completed text.
  Event feed(char c);
  const char* line() const { return buffer_; }

 private:
  char buffer_[kMaxLine + 1] = {};
  std::size_t length_ = 0;
  bool has_word_ = false;  // a character other than space or tab
  bool overflowed_ = false;
};

}  // namespace dynweigh::firmware
