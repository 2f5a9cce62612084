#include "dynweigh/firmware/console_line_reader.hpp"

namespace dynweigh::firmware {
namespace {
constexpr char kBackspace = '\x08';
constexpr char kDelete = '\x7f';

bool has_word(const char* text, std::size_t length) {
  for (std::size_t i = 0; i < length; ++i) {
    if (text[i] != ' ' && text[i] != '\t') return true;
  }
  return false;
}
}  // namespace

ConsoleLineReader::Event ConsoleLineReader::feed(char c) {
  echo_[0] = '\0';
  const bool after_cr = after_cr_;
  after_cr_ = c == '\r';
  if (c == '\0') return Event::none;  // would cut the line short where the parser reads it
  if (c == '\n' && after_cr) return Event::none;
  if (c == '\r' || c == '\n') return end_line();
  if (c == kBackspace || c == kDelete) {
    erase();
    return Event::none;
  }
  if (overflowed_) return Event::none;
  if (length_ == kMaxLine) {
    overflowed_ = true;
    return Event::none;
  }
  buffer_[length_++] = c;
  echo_[0] = c;
  echo_[1] = '\0';
  return Event::none;
}

ConsoleLineReader::Event ConsoleLineReader::end_line() {
  echo_[0] = '\n';
  echo_[1] = '\0';
  const bool was_too_long = overflowed_;
  const bool had_words = has_word(buffer_, length_);
  buffer_[length_] = '\0';
  length_ = 0;
  overflowed_ = false;
  if (was_too_long) return Event::too_long;
  return had_words ? Event::line : Event::none;
}

// A line already too long stays discarded: what the erasure would correct is no longer held.
void ConsoleLineReader::erase() {
  if (overflowed_ || length_ == 0) return;
  --length_;
  echo_[0] = '\b';
  echo_[1] = ' ';
  echo_[2] = '\b';
  echo_[3] = '\0';
}

}  // namespace dynweigh::firmware
