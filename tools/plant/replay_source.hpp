#pragma once
// Recorded raw samples for `dynweigh plant --replay FILE` (HIL replay): either a `readtestdata`
// capture (`<jiffy> <raw> <filtered> <marker>` lines; other lines such as `OK` are skipped) or a
// CSV whose header names a `raw` column (dynweigh-fw --csv, dynweigh sim).
#include <cstdint>
#include <string>
#include <vector>

namespace dynweigh::tools {

// Throws std::runtime_error with a one-line reason if the file cannot be read or holds no sample.
std::vector<std::int32_t> load_replay_samples(const std::string& path);

}  // namespace dynweigh::tools
