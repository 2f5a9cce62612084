#pragma once
// The one reader of captured load-cell samples, one per jiffy: `dynweigh replay` replays them open
// loop, `dynweigh plant --replay` sends them as the load-cell module. It reads
// - a `readtestdata` capture in the thesis' indicator format (`<jiffy> <raw> <filtered> <marker>` a
//   line; blank lines and the console's other lines, such as `OK` or an echoed command, are skipped;
//   an `ERR` line is refused; jiffies count on by one, or start again at 0 where another
//   printout follows),
// - a CSV whose header names a `raw` column (the dynweigh-fw --csv trace, dynweigh sim, dynweigh
//   term --out) and optionally `valve` or `marker`,
// - an inputs recording (dynweigh-fw --record): each jiffy's raw sample and the valve the live
//   run commanded.
// Any other binary file is refused.
#include <cstdint>
#include <string>
#include <vector>

namespace dynweigh::tools {

struct RecordedSample {
  std::int32_t raw_counts = 0;
  int valve = -1;  // the valve as recorded (0 closed, 1 half, 2 open), -1 if the file has none
};

struct RecordedSamples {
  std::string format;  // "readtestdata", "csv" or "inputs"
  std::vector<RecordedSample> samples;
  // The first jiffy the recorded valve was not closed, or -1.
  long first_open_jiffy() const;
};

// Limits that keep a wrong file from being read for minutes or eating the memory.
inline constexpr std::size_t kMaxSampleLineLength = 4096;
inline constexpr std::size_t kMaxSamples = 10'000'000;  // 27 hours of jiffies

// Throws std::runtime_error with a one-line reason (naming the line) if the file is unreadable,
// binary, malformed, or holds no sample.
RecordedSamples load_recorded_samples(const std::string& path);

}  // namespace dynweigh::tools
