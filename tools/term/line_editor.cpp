#include "line_editor.hpp"

namespace dynweigh::tools {
namespace {
constexpr char kCtrlA = 0x01, kCtrlC = 0x03, kCtrlD = 0x04, kCtrlE = 0x05, kBackspace = 0x08, kCtrlU = 0x15,
               kEscape = 0x1b, kDelete = 0x7f;
}  // namespace

LineEditor::Event LineEditor::feed(char byte) {
  if (escape_ == 1) {
    escape_ = (byte == '[' || byte == 'O') ? 2 : 0;
    escape_digits_.clear();
    return Event::none;
  }
  if (escape_ == 2) {
    if (byte >= '0' && byte <= '9') {
      escape_digits_.push_back(byte);
      return Event::none;
    }
    escape_ = 0;
    apply_escape(byte);
    return Event::none;
  }
  switch (byte) {
    case kEscape:
      escape_ = 1;
      return Event::none;
    case '\r':
    case '\n':
      completed_ = text_;
      if (!text_.empty() && (history_.empty() || history_.back() != text_)) history_.push_back(text_);
      text_.clear();
      cursor_ = 0;
      browsing_ = history_.size();
      return Event::line;
    case kCtrlC:
      return Event::end_of_input;
    case kCtrlD:
      if (text_.empty()) return Event::end_of_input;
      if (cursor_ < text_.size()) text_.erase(cursor_, 1);
      return Event::none;
    case kBackspace:
    case kDelete:
      if (cursor_ > 0) text_.erase(--cursor_, 1);
      return Event::none;
    case kCtrlA:
      cursor_ = 0;
      return Event::none;
    case kCtrlE:
      cursor_ = text_.size();
      return Event::none;
    case kCtrlU:
      text_.clear();
      cursor_ = 0;
      return Event::none;
    default:
      if (static_cast<unsigned char>(byte) >= 0x20) text_.insert(cursor_++, 1, byte);
      return Event::none;
  }
}

void LineEditor::apply_escape(char final_byte) {
  switch (final_byte) {
    case 'A':  // up: an older line
      if (browsing_ > 0) {
        if (browsing_ == history_.size()) unsent_ = text_;
        recall(browsing_ - 1);
      }
      return;
    case 'B':  // down: a newer line, then the unsent one
      if (browsing_ + 1 < history_.size()) {
        recall(browsing_ + 1);
      } else if (browsing_ + 1 == history_.size()) {
        browsing_ = history_.size();
        text_ = unsent_;
        cursor_ = text_.size();
      }
      return;
    case 'C':
      if (cursor_ < text_.size()) ++cursor_;
      return;
    case 'D':
      if (cursor_ > 0) --cursor_;
      return;
    case 'H':
      cursor_ = 0;
      return;
    case 'F':
      cursor_ = text_.size();
      return;
    case '~':  // ESC [ 3 ~ delete, 1/7 ~ home, 4/8 ~ end
      if (escape_digits_ == "3" && cursor_ < text_.size()) text_.erase(cursor_, 1);
      if (escape_digits_ == "1" || escape_digits_ == "7") cursor_ = 0;
      if (escape_digits_ == "4" || escape_digits_ == "8") cursor_ = text_.size();
      return;
    default:
      return;
  }
}

void LineEditor::recall(std::size_t index) {
  browsing_ = index;
  text_ = history_[index];
  cursor_ = text_.size();
}

std::string LineEditor::take_line() { return std::move(completed_); }

}  // namespace dynweigh::tools
