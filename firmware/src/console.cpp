#include "dynweigh/firmware/console.hpp"

#include <cstring>

namespace dynweigh::firmware {

void Console::receive(const char* bytes, std::size_t length, bool echo) {
  for (std::size_t i = 0; i < length; ++i) {
    const ConsoleLineReader::Event event = reader_.feed(bytes[i]);
    if (echo) ring_.write(reader_.echo());
    if (event == ConsoleLineReader::Event::none) continue;
    if (queue_count_ == kQueue) {
      error(3, "busy");  // more lines than a console can have in flight: refuse, do not lose silently
      continue;
    }
    Line& slot = queue_[(queue_head_ + queue_count_) % kQueue];
    slot.too_long = event == ConsoleLineReader::Event::too_long;
    std::strncpy(slot.text, slot.too_long ? "" : reader_.line(), sizeof slot.text);
    slot.text[sizeof slot.text - 1] = '\0';
    ++queue_count_;
  }
}

Console::Line* Console::next_line() {
  if (queue_count_ == 0 || answers_after_save_ > 0 || ring_.free_space() < kRoomForAnAnswer) return nullptr;
  return &queue_[queue_head_];
}

void Console::pop_line() {
  queue_head_ = (queue_head_ + 1) % kQueue;
  --queue_count_;
}

void Console::error(int code, const char* text) {
  ring_.write("ERR ");
  ring_.write_int(code);
  ring_.put(' ');
  ring_.line(text);
}

void Console::release_held_answers(bool save_failed) {
  for (; answers_after_save_ > 0; --answers_after_save_) {
    if (save_failed) {
      error(4, "fault nvm_error");
    } else {
      ring_.line("OK");
    }
  }
}

}  // namespace dynweigh::firmware
