#pragma once
// A console fed line by line, each line only once the indicator has finished the previous
// command: how a script (or a person waiting for OK) drives an indicator. At the end of the
// script the loop finishes the command in progress and stops. A polled source (stdin) may have no
// line yet: the console then reads nothing this jiffy and asks again in the next, so the control
// loop never waits for a line.
#include <functional>
#include <string>

#include "dynweigh/hal/ports.hpp"

namespace dynweigh::hal::host {

class ScriptedConsole final : public ConsolePort {
 public:
  using LineSource = std::function<bool(std::string&)>;  // false at end of input
  enum class Poll { line, nothing_yet, ended };
  using PolledSource = std::function<Poll(std::string&)>;
  using Sink = std::function<void(const char*, std::size_t)>;

  ScriptedConsole(LineSource source, Sink sink)
      : source_([source = std::move(source)](std::string& line) { return source(line) ? Poll::line : Poll::ended; }),
        sink_(std::move(sink)) {}
  ScriptedConsole(PolledSource source, Sink sink) : source_(std::move(source)), sink_(std::move(sink)) {}

  // The indicator's `busy` from the last jiffy: no new line while it is set.
  void set_indicator_busy(bool busy) { busy_ = busy; }
  bool input_ended() const { return ended_; }
  bool line_in_transit() const { return !pending_.empty(); }
  // More input may come after all (an interactive source): ask the source again.
  void reopen() { ended_ = false; }

  std::size_t read(char* destination, std::size_t capacity) override;
  void write(const char* data, std::size_t length) override { sink_(data, length); }

 private:
  PolledSource source_;
  Sink sink_;
  std::string pending_;
  bool busy_ = false;
  bool ended_ = false;
};

}  // namespace dynweigh::hal::host
