#include "dynweigh/firmware/console_line_reader.hpp"

namespace dynweigh::firmware {

ConsoleLineReader::Event ConsoleLineReader::feed(char c) {
  if (c == '\0') return Event::none;  // would cut the line short where the parser reads it
  if (c == '\r' || c == '\n') {
    // CR LF yields an empty second line, which is ignored like any empty line.
    const bool was_too_long = overflowed_;
    const bool had_words = has_word_;
    buffer_[length_] = '\0';
    length_ = 0;
    has_word_ = false;
    overflowed_ = false;
    if (was_too_long) return Event::too_long;
    return had_words ? Event::line : Event::none;
  }
  if (overflowed_) return Event::none;
  if (length_ == kMaxLine) {
    overflowed_ = true;
    return Event::none;
  }
  buffer_[length_++] = c;
  if (c != ' ' && c != '\t') has_word_ = true;
  return Event::none;
}

}  // namespace dynweigh::firmware
