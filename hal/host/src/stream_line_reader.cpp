#include "dynweigh/hal/host/stream_line_reader.hpp"

#include <poll.h>
#include <unistd.h>

#include <cerrno>

namespace dynweigh::hal::host {

bool StreamLineReader::take_line(std::string& line) {
  while (chunk_used_ < chunk_length_) {
    const char c = chunk_[chunk_used_++];
    if (c == '\n') {
      line.swap(line_);
      line_.clear();
      return true;
    }
    if (c == '\0') continue;
    if (line_.size() < kKeptCharacters) line_.push_back(c);
  }
  return false;
}

StreamLineReader::Result StreamLineReader::next(std::string& line, int wait_ms) {
  for (;;) {
    const Result result = read_chunk(line, wait_ms);
    if (result != Result::nothing_yet || wait_ms >= 0 || (stop_ && stop_())) return result;
  }
}

StreamLineReader::Result StreamLineReader::read_chunk(std::string& line, int wait_ms) {
  if (take_line(line)) return Result::line;
  if (ended_) return Result::ended;
  pollfd ready{fd_, POLLIN, 0};
  const int n = ::poll(&ready, 1, wait_ms);
  if (n <= 0) return Result::nothing_yet;  // nothing yet, or a signal
  const ssize_t got = ::read(fd_, chunk_, sizeof chunk_);
  if (got < 0) {
    if (errno == EINTR || errno == EAGAIN) return Result::nothing_yet;
    ended_ = true;  // a stream that cannot be read any more has ended
  } else if (got == 0) {
    ended_ = true;
  }
  chunk_used_ = 0;
  chunk_length_ = got > 0 ? std::size_t(got) : 0;
  if (take_line(line)) return Result::line;
  if (!ended_) return Result::nothing_yet;
  if (line_.empty()) return Result::ended;
  line.swap(line_);  // the last line, without its LF
  line_.clear();
  return Result::line;
}

}  // namespace dynweigh::hal::host
