#pragma once
// Console lines from a byte stream (stdin: a pipe, a file, a terminal) without ever waiting on it
// unless asked to: each call reads at most one chunk of what is ready, so a control loop that
// polls it keeps its jiffy whatever the stream does. A line longer than the console's 80
// characters keeps only its first 81 (enough for the indicator to answer `ERR 2 line too long`),
// the rest is dropped as it comes, so a line that never ends (`< /dev/zero`) costs no memory. NUL
// bytes are dropped, as the indicator's own line reader drops them.
#include <cstddef>
#include <functional>
#include <string>

#include "dynweigh/firmware/console_line_reader.hpp"

namespace dynweigh::hal::host {

class StreamLineReader {
 public:
  enum class Result { line, nothing_yet, ended };
  static constexpr std::size_t kKeptCharacters = firmware::ConsoleLineReader::kMaxLine + 1;
  static constexpr std::size_t kChunk = 4096;

  // `stop`, if given, ends a wait for a whole line (a signal handler's flag).
  explicit StreamLineReader(int fd, std::function<bool()> stop = {}) : fd_(fd), stop_(std::move(stop)) {
    line_.reserve(kKeptCharacters);
  }

  // The next line (without its LF). wait_ms 0: reads at most one chunk of what the stream has
  // ready, never waits; `nothing_yet` if that made no whole line. wait_ms -1: waits for a whole
  // line or the end of input; `nothing_yet` only when a signal interrupted the wait and `stop` says so.
  Result next(std::string& line, int wait_ms = 0);

 private:
  bool take_line(std::string& line);  // from the chunk read last
  Result read_chunk(std::string& line, int wait_ms);
  int fd_;
  std::function<bool()> stop_;
  char chunk_[kChunk];
  std::size_t chunk_used_ = 0, chunk_length_ = 0;
  std::string line_;  // at most kKeptCharacters: the rest of a longer line is dropped
  bool ended_ = false;
};

}  // namespace dynweigh::hal::host
