#pragma once
// Raw load-cell samples recorded one per jiffy, for an open-loop replay: a `readtestdata` capture
// in the thesis' indicator format (`<jiffy> <raw> <filtered> <marker>` a line; blank lines, `OK`
// and an echoed `readtestdata` are skipped), or a CSV whose header names a `raw` column (the
// dynweigh-fw --csv trace, dynweigh sim, dynweigh term --out) and optionally `valve` or `marker`.
#include <cstdint>
#include <string>
#include <vector>

namespace dynweigh::tools {

struct RecordedSample {
  std::int32_t raw_counts = 0;
  int valve = -1;  // the valve as recorded (0 closed, 1 half, 2 open), -1 if the file has none
};

struct RecordedSamples {
  std::string format;  // "readtestdata" or "csv"
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
