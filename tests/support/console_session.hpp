#pragma once
// Drives a LockstepSession through its console as a script would: one line at a time, each once
// the previous command has finished; collects everything the indicator printed.
#include <cstdint>
#include <deque>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "dynweigh/hal/host/lockstep_session.hpp"
#include "dynweigh/hal/host/scripted_console.hpp"
#include "dynweigh/sim/scene.hpp"
#include "support/string_console.hpp"

namespace dynweigh::testing {

class ConsoleSession {
 public:
  explicit ConsoleSession(const sim::Scene& scene = sim::default_scene(), std::uint64_t seed = 1,
                          std::optional<firmware::PersistentSettings> settings = std::nullopt,
                          hal::SettingsStore* store = nullptr)
      : session_(scene, seed, settings, store),
        console_([this](std::string& line) { return next_line(line); },
                 [this](const char* data, std::size_t n) { output_.append(data, n); }) {}

  // Sends the lines and runs until the last command has finished (or `max_jiffies` pass).
  std::string run(const std::vector<std::string>& lines, std::uint32_t max_jiffies = 20000) {
    output_.clear();
    for (const auto& line : lines) script_.push_back(line);
    console_.reopen();
    for (std::uint32_t i = 0; i < max_jiffies; ++i) {
      const firmware::Outputs out = step();
      if (script_.empty() && !out.busy && !console_.line_in_transit()) return output_;
    }
    return output_;
  }

  // Lets `jiffies` pass with no input.
  void idle(std::uint32_t jiffies) {
    for (std::uint32_t i = 0; i < jiffies; ++i) step();
  }

  firmware::Outputs step() {
    const firmware::Outputs out = session_.step(console_);
    console_.set_indicator_busy(out.busy);
    if (out.settings_changed) ++saves_asked_;
    trace_.push_back(session_.last_row());
    return out;
  }

  // Raw bytes straight into the indicator, bypassing the line-at-a-time script.
  std::string send_raw(const std::string& bytes, std::uint32_t jiffies = 5) {
    StringConsole raw;
    raw.pending = bytes;
    for (std::uint32_t i = 0; i < jiffies; ++i) session_.step(raw);
    return raw.output;
  }

  hal::host::LockstepSession& session() { return session_; }
  const std::vector<hal::host::TraceRow>& trace() const { return trace_; }
  // How many jiffies asked the board to save the settings, since the session began.
  std::uint32_t saves_asked() const { return saves_asked_; }

 private:
  bool next_line(std::string& line) {
    if (script_.empty()) return false;
    line = script_.front();
    script_.pop_front();
    return true;
  }

  std::uint32_t saves_asked_ = 0;
  hal::host::LockstepSession session_;
  hal::host::ScriptedConsole console_;
  std::deque<std::string> script_;
  std::string output_;
  std::vector<hal::host::TraceRow> trace_;
};

inline std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The lines of `output` that begin with `prefix` ("RESULT ", "MATERIAL "), in order.
inline std::vector<std::string> lines_starting(const std::string& output, const std::string& prefix) {
  std::vector<std::string> found;
  for (const std::string& line : lines_of(output)) {
    if (line.rfind(prefix, 0) == 0) found.push_back(line);
  }
  return found;
}

// The value of `key=` in a key=value line, or empty.
inline std::string field(const std::string& line, const std::string& key) {
  const auto at = line.find(key + "=");
  if (at == std::string::npos) return "";
  const auto begin = at + key.size() + 1;
  return line.substr(begin, line.find(' ', begin) - begin);
}

}  // namespace dynweigh::testing
