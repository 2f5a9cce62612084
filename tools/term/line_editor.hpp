#pragma once
// The interactive console's input line: printable characters, backspace, delete, left/right,
// Home/End (and Ctrl-A/Ctrl-E), Ctrl-U to clear, up/down through the history of sent lines.
// It only edits; the caller owns the terminal and redraws with prompt_text() and cursor().
#include <cstddef>
#include <string>
#include <vector>

namespace dynweigh::tools {

class LineEditor {
 public:
  enum class Event { none, line, end_of_input };

  // Feeds one byte from the keyboard. `line`: a line is complete, take it with take_line().
  Event feed(char byte);
  std::string take_line();

  const std::string& text() const { return text_; }
  std::size_t cursor() const { return cursor_; }
  const std::vector<std::string>& history() const { return history_; }

 private:
  void apply_escape(char final_byte);
  void recall(std::size_t index);

  std::string text_;
  std::size_t cursor_ = 0;
  std::vector<std::string> history_;
  std::size_t browsing_ = 0;  // history_.size(): editing a new line
  std::string unsent_;        // the new line while browsing the history
  std::string completed_;
  int escape_ = 0;            // 0 none, 1 after ESC, 2 inside ESC [
  std::string escape_digits_;
};

}  // namespace dynweigh::tools
