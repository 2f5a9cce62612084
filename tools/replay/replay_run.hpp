#pragma once
// Recorded inputs through the same firmware::Indicator::step the firmware runs, jiffy by jiffy,
// and what it decided: recorded samples through the step give the same decisions, bit
// for bit.
//
// Two kinds of replay, and the difference matters to whoever reads the result:
// - an inputs recording (dynweigh-fw --record) replays closed-loop exactly: the indicator gets the
//   very bytes it got live, so it decides the very same things; each jiffy is checked against the
//   outputs the live run recorded.
// - raw samples (a readtestdata capture, a CSV with a raw column) replay open loop: the samples
//   were taken with the valve as it was then, so the valve decisions the replay prints did not act
//   on them. They show what the firmware *would have* decided, e.g. where it would have cut off.
//   So does an inputs recording whose doses are given another strategy.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "dynweigh/firmware/dosing_strategy.hpp"
#include "dynweigh/firmware/io.hpp"
#include "dynweigh/firmware/persistent_settings.hpp"
#include "recorded_samples.hpp"

namespace dynweigh::tools {

struct ReplayOptions {
  // Raw replays: console lines, each sent once the previous command has finished (as a person
  // waiting for OK would), the first at `start_jiffy`.
  std::vector<std::string> console_lines;
  // -1: the jiffy the recorded valve first opened (a `dose` opens the valve the jiffy it arrives,
  // so its decisions line up with the recording), or 0 if the file shows no valve.
  long start_jiffy = -1;
  // Raw replays: the indicator's calibration and parameters.
  firmware::PersistentSettings settings;
  // Inputs recordings: run every recorded `dose` with this strategy instead (open loop then).
  std::optional<firmware::DosingStrategy> strategy;
};

// What the firmware saw and decided in one jiffy.
struct ReplayRow {
  std::uint32_t jiffy = 0;
  std::int32_t raw_counts = 0;
  float gross_g = 0.0f;     // the raw sample through the calibration, before filter and tare
  float filtered_g = 0.0f;  // the display filter's net weight
  bool has_prediction = false;
  float prediction_g = 0.0f;  // the model's final weight if the valve were told to close now
  firmware::ValveCommand valve = firmware::ValveCommand::closed;
  firmware::IndicatorState state = firmware::IndicatorState::idle;
  int recorded_valve = -1;  // what the recording's valve did (live decision or marker), -1 unknown
};

struct ReplaySummary {
  std::string format;  // inputs, readtestdata, csv
  std::string source;  // an inputs recording's note on what made it
  std::uint64_t jiffies = 0;
  bool open_loop = false;
  std::size_t commands_sent = 0;  // raw replays
  // Raw replays: each console line the indicator answered with ERR, as "'<line>': ERR ...", and
  // the lines never sent because the samples ran out first.
  std::vector<std::string> refusals;
  std::vector<std::string> unsent;
  std::size_t doses_rewritten = 0;
  long dose_start_jiffy = -1;     // the jiffy the first dose began
  long cutoff_jiffy = -1;         // the jiffy the firmware first commanded the valve closed in a dose
  std::vector<std::string> results;  // RESULT lines, as printed
  bool checked = false;              // the recording held the live outputs and was compared
  long first_mismatch_jiffy = -1;
  std::string mismatch;              // what differed first
};

struct ReplaySinks {
  std::function<void(const ReplayRow&)> row;
  std::function<void(const char*, std::size_t)> console;
  std::function<void(std::uint64_t done, std::uint64_t total)> progress;
};

// Throws std::runtime_error (one line) on a damaged file or bad options.
ReplaySummary replay_inputs_recording(const std::string& path, const ReplayOptions& options, const ReplaySinks& sinks);
ReplaySummary replay_samples(const RecordedSamples& samples, const ReplayOptions& options, const ReplaySinks& sinks);

}  // namespace dynweigh::tools
