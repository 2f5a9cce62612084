#pragma once
// The console: typed bytes made lines (ConsoleLineReader), a few lines queued while a command
// runs, and the transmit ring the answers go into and the board drains at its own pace. A queued
// line runs once the ring has room for its whole answer, so an answer is never cut short. The
// commands: the table in console_commands.cpp, the handlers grouped by what they act on.
#include <cstddef>
#include <cstdint>

#include "dynweigh/firmware/console_line_reader.hpp"
#include "dynweigh/firmware/io.hpp"
#include "dynweigh/firmware/parameters.hpp"
#include "dynweigh/firmware/text_writer.hpp"

namespace dynweigh::firmware {

class Console {
 public:
  // The longest answer a command writes at once (the `param` listing; `help` and `learn` are checked
  // against it where they are written).
  static constexpr std::size_t kLongestAnswerBytes = kParameterListingMaxBytes;
  // A command runs once its whole answer fits: the longest, and the answer a running command (dose,
  // zero, cal) may still add to it.
  static constexpr std::size_t kRoomForARunningAnswer = 256;
  static constexpr std::size_t kRoomForAnAnswer = kLongestAnswerBytes + kRoomForARunningAnswer;
  // One line of a listing printed a few a jiffy (`readtestdata`).
  static constexpr std::size_t kRoomForARecord = 48;
  static constexpr std::size_t kQueue = 4;

  struct Line {
    char text[ConsoleLineReader::kMaxLine + 1];
    bool too_long;  // discarded whole: `text` is empty
  };

  // The bytes that arrived this jiffy, made lines; `echo` writes what a terminal should show.
  void receive(const char* bytes, std::size_t length, bool echo);
  // The oldest queued line if its answer can be written now (no answer held, room in the ring),
  // else nullptr. pop_line() once it has run.
  Line* next_line();
  void pop_line();
  std::size_t queued() const { return queue_count_; }

  void put(char c) { ring_.put(c); }
  void write(const char* text) { ring_.write(text); }
  void write_int(std::int64_t value) { ring_.write_int(value); }
  void write_decimal(float value, int max_decimals) { ring_.write_decimal(value, max_decimals); }
  void line(const char* text) { ring_.line(text); }
  // `ERR <code> <text>`.
  void error(int code, const char* text);
  std::size_t free_space() const { return ring_.free_space(); }
  std::size_t drain(char* destination, std::size_t capacity) { return ring_.drain(destination, capacity); }

  // A command that changed the settings answers once the board has said whether it saved them.
  void hold_ok() { ++answers_after_save_; }
  bool answers_held() const { return answers_after_save_ > 0; }
  // The held answers: OK each, or the storage's fault when the save failed.
  void release_held_answers(bool save_failed);

 private:
  ConsoleLineReader reader_;
  Line queue_[kQueue];
  std::size_t queue_head_ = 0, queue_count_ = 0;
  TextWriter ring_;
  std::uint8_t answers_after_save_ = 0;
};

static_assert(Console::kRoomForAnAnswer + Console::kRoomForARecord <= TextWriter::kCapacity,
              "the console ring cannot hold the longest answer: enlarge TextWriter::kCapacity");

}  // namespace dynweigh::firmware
