#pragma once
// Assembles console lines: a line ends at CR, LF or CR LF, empty lines are ignored, and a line
// longer than 80 characters is discarded whole (docs/console.md) and reported once at its end. A line of
// only spaces and tabs is empty too, and NUL bytes (a UART break, terminal padding) are dropped,
// so every line the reader completes is a command the indicator answers exactly once.
//
// Backspace (0x08) and DEL (0x7f, what most terminals send for the backspace key) erase the last
// character typed, as a terminal user expects. echo() tells what a terminal should show for the
// byte just fed: the character, "\b \b" for an erasure, "\n" at the end of a line (once for CR LF).
#include <cstddef>

namespace dynweigh::firmware {

class ConsoleLineReader {
 public:
  static constexpr std::size_t kMaxLine = 80;

  enum class Event { none, line, too_long };
  // Feeds one byte; on Event::line, line() holds the completed text.
  Event feed(char c);
  const char* line() const { return buffer_; }
  // What to echo for the byte last fed ("" for nothing).
  const char* echo() const { return echo_; }

 private:
  Event end_line();
  void erase();

  char buffer_[kMaxLine + 1] = {};
  std::size_t length_ = 0;
  bool overflowed_ = false;
  bool after_cr_ = false;  // an LF right after a CR ends no second line and echoes nothing
  char echo_[4] = {};
};

}  // namespace dynweigh::firmware
