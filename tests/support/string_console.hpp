#pragma once
// A console port over two strings: the bytes still to send to the indicator, and what it answered.
#include <algorithm>
#include <string>

#include "dynweigh/hal/ports.hpp"

namespace dynweigh::testing {

struct StringConsole final : hal::ConsolePort {
  std::size_t read(char* destination, std::size_t capacity) override {
    const std::size_t n = std::min(capacity, pending.size());
    pending.copy(destination, n);
    pending.erase(0, n);
    return n;
  }
  void write(const char* data, std::size_t n) override { output.append(data, n); }

  std::string pending;
  std::string output;
};

// Whether the console's last line is a command's final answer (OK or ERR): the command is done.
inline bool ends_with_answer(const std::string& text) {
  if (text.empty() || text.back() != '\n') return false;
  const std::size_t start = text.rfind('\n', text.size() - 2);
  const std::string last = text.substr(start == std::string::npos ? 0 : start + 1);
  return last == "OK\n" || last.rfind("ERR ", 0) == 0;
}

}  // namespace dynweigh::testing
