#pragma once
// A progress bar on stderr for work that runs longer than a second (replay, bench, sweeps, DEM).
// Silent for the first second, so quick runs print nothing, and redrawn at most ten times a
// second, so update() may be called every iteration. It draws only on a terminal: logs, pipes
// and the tests' captured stderr stay clean (a tool's error is still one line). `--quiet`
// switches it off; DYNWEIGH_PROGRESS=1 forces it on (to test it, or to watch a job through a pipe).
//
//   tools::ProgressBar bar("replay", total_jiffies, !quiet);
//   for (...) bar.update(done);
//   bar.finish();   // or let the destructor do it
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace dynweigh::tools {

class ProgressBar {
 public:
  // `total` 0: unknown, shows a count instead of a bar.
  ProgressBar(std::string label, std::uint64_t total, bool enabled = true)
      : label_(std::move(label)), total_(total), enabled_(enabled && wanted()), start_(Clock::now()) {}
  ~ProgressBar() { finish(); }
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void set_total(std::uint64_t total) { total_ = total; }

  void update(std::uint64_t done) {
    if (!enabled_) return;
    const auto now = Clock::now();
    if (now - start_ < kQuietFor || now - last_draw_ < kRedrawEvery) return;
    last_draw_ = now;
    draw(done, now);
  }

  // Ends the bar's line (if one was drawn) so the next output starts clean.
  void finish() {
    if (drawn_) std::fputc('\n', stderr);
    drawn_ = false;
    enabled_ = false;
  }

  bool enabled() const { return enabled_; }

 private:
  using Clock = std::chrono::steady_clock;
  static constexpr std::chrono::milliseconds kQuietFor{1000};
  static constexpr std::chrono::milliseconds kRedrawEvery{100};
  static constexpr int kWidth = 30;

  static bool wanted() {
    const char* force = std::getenv("DYNWEIGH_PROGRESS");
    if (force && std::strcmp(force, "0") == 0) return false;
    if (force && std::strcmp(force, "1") == 0) return true;
    return ::isatty(STDERR_FILENO) == 1;
  }

  void draw(std::uint64_t done, Clock::time_point now) {
    const double elapsed_s = std::chrono::duration<double>(now - start_).count();
    if (total_ > 0) {
      const double fraction = done >= total_ ? 1.0 : double(done) / double(total_);
      const int filled = int(fraction * kWidth);
      std::string bar(std::size_t(filled), '#');
      bar.resize(kWidth, '.');
      const double eta_s = fraction > 0 ? elapsed_s * (1.0 - fraction) / fraction : 0.0;
      std::fprintf(stderr, "\r%s [%s] %3d%%  %.0f s left ", label_.c_str(), bar.c_str(), int(fraction * 100.0), eta_s);
    } else {
      std::fprintf(stderr, "\r%s %llu  %.0f s ", label_.c_str(), static_cast<unsigned long long>(done), elapsed_s);
    }
    std::fflush(stderr);
    drawn_ = true;
  }

  std::string label_;
  std::uint64_t total_;
  bool enabled_;
  bool drawn_ = false;
  Clock::time_point start_;
  Clock::time_point last_draw_{};
};

}  // namespace dynweigh::tools
