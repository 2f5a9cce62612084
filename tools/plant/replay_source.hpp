#pragma once
// Recorded raw samples for `dynweigh plant --replay FILE` (HIL replay): a `readtestdata` capture
// (`<jiffy> <raw> <filtered> <marker>` lines; other lines such as `OK` are skipped), a CSV whose
// header names a `raw` column (dynweigh-fw --csv, dynweigh sim), or an inputs recording
// (dynweigh-fw --record: each jiffy's raw sample). Any other binary file is refused.
#include <cstdint>
#include <string>
#include <vector>

namespace dynweigh::tools {

// Throws std::runtime_error with a one-line reason if the file cannot be read, is binary but not an
// inputs recording, or holds no sample.
std::vector<std::int32_t> load_replay_samples(const std::string& path);

}  // namespace dynweigh::tools
