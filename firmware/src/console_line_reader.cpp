#include "dynweigh/firmware/console_line_reader.hpp"

namespace dynweigh::firmware {

ConsoleLineReader::Event ConsoleLineReader::feed(char c) {
  if (c == '\r' || c == '\n') {
    // CR LF yields an empty second line, which is ignored like any empty line.
    const bool was_too_long = overflowed_;
    const bool had_text = length_ > 0;
    buffer_[length_] = '\0';
    length_ = 0;
    overflowed_ = false;
    if (was_too_long) return Event::too_long;
    return had_text ? Event::line : Event::none;
  }
  if (overflowed_) return Event::none;
  if (length_ == kMaxLine) {
    overflowed_ = true;
    return Event::none;
  }
  buffer_[length_++] = c;
  return Event::none;
}

}  // namespace dynweigh::firmware
