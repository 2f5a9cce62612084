// dynweigh replay: recorded samples or inputs through the firmware's own step function, and what it
// decided each jiffy (replay_run.hpp says which replays are exact and which are open loop).
#include <CLI/CLI.hpp>

#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "dynweigh/hal/host/file_settings_store.hpp"
#include "dynweigh/hal/host/inputs_recording.hpp"
#include "dynweigh/hal/host/simulated_plant_ports.hpp"
#include "dynweigh/sim/plant.hpp"
#include "dynweigh/sim/scene.hpp"
#include "finite_range.hpp"
#include "progress_bar.hpp"
#include "replay_commands.hpp"
#include "replay_run.hpp"
#include "command_line.hpp"

namespace dynweigh::tools {
namespace {

constexpr long long kMaxFileBytes = 2LL << 30;  // a day of inputs is far less; bigger is a wrong file
constexpr std::size_t kAutoTargetAverage = 20;   // samples averaged for the fill a recording reached

struct Arguments {
  std::string file;
  std::string strategy;
  std::string dose = "";
  std::vector<std::string> send;
  long at = -1;
  std::string csv;
  std::string console_out;
  std::string scene = "default";
  std::uint64_t seed = 1;
  std::string nvm;
  std::optional<double> zero_counts;
  std::optional<double> counts_per_gram;
  bool quiet = false;
};

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

File open_for_writing(const std::string& path) {
  File f(std::fopen(path.c_str(), "w"));
  if (!f) throw std::runtime_error("cannot write " + path);
  return f;
}

void check_size(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw std::runtime_error("cannot read " + path);
  if (S_ISDIR(st.st_mode)) throw std::runtime_error(path + " is a directory");
  if (st.st_size > kMaxFileBytes) {
    throw std::runtime_error(path + ": " + std::to_string(st.st_size) + " bytes, more than the 2 GiB a replay reads");
  }
}

firmware::PersistentSettings raw_replay_settings(const Arguments& a) {
  firmware::PersistentSettings settings;
  if (!a.nvm.empty()) {
    hal::host::FileSettingsStore store(a.nvm);
    if (!store.load(settings)) throw std::runtime_error(a.nvm + ": no valid settings record");
  } else {
    const auto scene = sim::scene_by_name(a.scene);
    if (!scene) throw std::runtime_error("unknown scene '" + a.scene + "'");
    const sim::Plant plant(*scene, a.seed);
    settings = hal::host::factory_settings(plant);
  }
  if (a.zero_counts) {
    settings.calibration.zero_counts = std::int32_t(std::floor(*a.zero_counts));
    settings.calibration.zero_fraction = float(*a.zero_counts - std::floor(*a.zero_counts));
    settings.calibration.zero_set = true;
  }
  if (a.counts_per_gram) {
    settings.calibration.counts_per_gram = float(*a.counts_per_gram);
    settings.calibration.span_set = true;
  }
  return settings;
}

double mean_raw(const RecordedSamples& s, std::size_t from, std::size_t to) {
  double sum = 0;
  for (std::size_t i = from; i < to; ++i) sum += s.samples[i].raw_counts;
  return to > from ? sum / double(to - from) : 0.0;
}

// The fill the recording reached, in grams: what to ask of the firmware to compare its cutoff with
// the recorded one.
long auto_target_g(const RecordedSamples& s, long start, const firmware::PersistentSettings& settings) {
  const std::size_t n = s.samples.size();
  if (start < 1 || n < std::size_t(start) + kAutoTargetAverage) return -1;
  const std::size_t before = std::size_t(start);
  const double empty = mean_raw(s, before > kAutoTargetAverage ? before - kAutoTargetAverage : 0, before);
  const double full = mean_raw(s, n - kAutoTargetAverage, n);
  return std::lround((full - empty) / settings.calibration.counts_per_gram);
}

long recorded_cutoff(const RecordedSamples& s) {
  for (std::size_t i = 1; i < s.samples.size(); ++i) {
    if (s.samples[i - 1].valve > 0 && s.samples[i].valve == 0) return long(i);
  }
  return -1;
}

void print_summary(const ReplaySummary& s) {
  std::printf("format=%s\njiffies=%llu\nopen_loop=%d\n", s.format.c_str(), static_cast<unsigned long long>(s.jiffies),
              s.open_loop ? 1 : 0);
  if (!s.source.empty()) std::printf("source=%s\n", s.source.c_str());
  if (s.format != "inputs") std::printf("commands_sent=%zu\n", s.commands_sent);
  if (s.doses_rewritten > 0) std::printf("doses_rewritten=%zu\n", s.doses_rewritten);
  std::printf("dose_start_jiffy=%ld\ncutoff_jiffy=%ld\nresults=%zu\n", s.dose_start_jiffy, s.cutoff_jiffy,
              s.results.size());
  if (!s.results.empty()) {
    // The last RESULT's fields as result_<key>=<value>.
    std::string line = s.results.back().substr(7);
    std::size_t at = 0;
    while (at < line.size()) {
      const std::size_t end = std::min(line.find(' ', at), line.size());
      std::printf("result_%s\n", line.substr(at, end - at).c_str());
      at = end + 1;
    }
  }
  if (s.checked) {
    std::printf("matches_recording=%d\n", s.first_mismatch_jiffy < 0 ? 1 : 0);
    if (s.first_mismatch_jiffy >= 0) std::printf("mismatch_jiffy=%ld\n", s.first_mismatch_jiffy);
  }
}

std::string and_more(std::size_t others) {
  return others == 0 ? "" : " (and " + std::to_string(others) + " more)";
}

// Raw replays: a console line the indicator refused, or one the samples ran out before, is a
// replay that did not do what was asked.
int report_console_failures(const ReplaySummary& s) {
  if (!s.refusals.empty()) {
    std::fprintf(stderr, "dynweigh replay: the indicator refused %s%s\n", s.refusals.front().c_str(),
                 and_more(s.refusals.size() - 1).c_str());
    return 4;
  }
  if (!s.unsent.empty()) {
    std::fprintf(stderr, "dynweigh replay: the samples ended before '%s' could be sent%s\n", s.unsent.front().c_str(),
                 and_more(s.unsent.size() - 1).c_str());
    return 4;
  }
  return 0;
}

int run(const Arguments& a) {
  check_size(a.file);
  ReplayOptions options;
  if (!a.strategy.empty()) {
    firmware::DosingStrategy strategy;
    if (!firmware::parse_strategy(a.strategy.c_str(), strategy)) throw std::runtime_error("unknown strategy '" + a.strategy + "'");
    options.strategy = strategy;
  }
  File csv, console;
  if (!a.csv.empty()) csv = open_for_writing(a.csv);
  if (!a.console_out.empty()) console = open_for_writing(a.console_out);
  if (csv) std::fprintf(csv.get(), "t_s,jiffy,raw,gross_g,filtered_g,prediction_g,valve,state,recorded_valve\n");

  ProgressBar bar("replay", 0, !a.quiet);
  ReplaySinks sinks;
  if (csv) {
    sinks.row = [&csv](const ReplayRow& r) {
      std::fprintf(csv.get(), "%.2f,%u,%d,%.1f,%.1f,", double(r.jiffy) * 0.01, r.jiffy, r.raw_counts, double(r.gross_g),
                   double(r.filtered_g));
      if (r.has_prediction) std::fprintf(csv.get(), "%.1f", double(r.prediction_g));
      std::fprintf(csv.get(), ",%d,%d,", int(r.valve), int(r.state));
      if (r.recorded_valve >= 0) std::fprintf(csv.get(), "%d", r.recorded_valve);
      std::fputc('\n', csv.get());
    };
  }
  if (console) sinks.console = [&console](const char* data, std::size_t n) { std::fwrite(data, 1, n, console.get()); };
  sinks.progress = [&bar](std::uint64_t done, std::uint64_t total) {
    bar.set_total(total);
    bar.update(done);
  };

  ReplaySummary summary;
  long recorded_close = -1;
  if (hal::host::InputsRecordingReader::is_recording(a.file)) {
    if (!a.dose.empty() || !a.send.empty()) {
      throw std::runtime_error("an inputs recording replays its own console; --dose/--send are for raw samples");
    }
    summary = replay_inputs_recording(a.file, options, sinks);
  } else {
    const RecordedSamples samples = load_recorded_samples(a.file);
    options.settings = raw_replay_settings(a);
    options.start_jiffy = a.at;
    const long start = a.at >= 0 ? a.at : std::max(0L, samples.first_open_jiffy());
    const std::string strategy_word = a.strategy.empty() ? "" : " " + a.strategy;
    if (!a.dose.empty()) {
      long target = 0;
      if (a.dose == "auto") {
        target = auto_target_g(samples, start, options.settings);
        if (target <= 0) throw std::runtime_error("--dose auto: the file shows no valve opening and filling");
      } else {
        std::size_t used = 0;
        try {
          target = std::stol(a.dose, &used);
        } catch (const std::logic_error&) {
          used = 0;
        }
        if (used != a.dose.size() || target <= 0) throw std::runtime_error("--dose takes grams > 0 or 'auto', not '" + a.dose + "'");
      }
      options.console_lines.push_back("dose " + std::to_string(target) + strategy_word);
    } else if (!a.strategy.empty() && a.send.empty()) {
      throw std::runtime_error("--strategy on raw samples needs --dose G (or --dose auto)");
    }
    for (const auto& line : a.send) options.console_lines.push_back(line);
    recorded_close = recorded_cutoff(samples);
    if (!a.quiet) {
      std::fprintf(stderr,
                   "dynweigh replay: OPEN LOOP: the valve decisions printed did not act on this recording; its samples "
                   "follow the valve as it was when it was recorded\n");
    }
    options.strategy.reset();
    summary = replay_samples(samples, options, sinks);
  }
  bar.finish();
  if (summary.open_loop && summary.format == "inputs" && !a.quiet) {
    std::fprintf(stderr, "dynweigh replay: OPEN LOOP: the doses run with another strategy than recorded; the samples "
                         "follow the valve as it was when it was recorded\n");
  }
  print_summary(summary);
  if (recorded_close >= 0) std::printf("recorded_cutoff_jiffy=%ld\n", recorded_close);
  if (!a.csv.empty()) std::printf("csv=%s\n", a.csv.c_str());
  if (summary.checked && summary.first_mismatch_jiffy >= 0) {
    std::fprintf(stderr, "dynweigh replay: jiffy %ld differs from the recording: %s\n", summary.first_mismatch_jiffy,
                 summary.mismatch.c_str());
    return 3;
  }
  return report_console_failures(summary);
}

}  // namespace

int run_replay_command(int argc, char** argv) {
  Arguments a;
  CLI::App app{
      "dynweigh replay: recorded samples through the firmware's own Indicator::step; prints what it decided.\n"
      "FILE is an inputs recording (dynweigh-fw --record: replays bit for bit, checked against the live run),\n"
      "a readtestdata capture (`<jiffy> <raw> <filtered> <marker>` lines; OK and blank lines skipped), or a\n"
      "CSV with a `raw` column (dynweigh-fw --csv, dynweigh term --out). Raw samples replay OPEN LOOP: the\n"
      "valve decisions did not act on the recording. Summary as key=value lines on stdout.\n"
      "Exit status: 0 done; 1 bad file or option; 3 the replay differs from the recording; 4 the indicator\n"
      "answered ERR to a --dose/--send line (shown on stderr), or the samples ended before it was sent."};
  app.add_option("file", a.file, "inputs recording, readtestdata capture or CSV with a raw column")->required();
  app.add_option("--strategy", a.strategy, "model, preact, twostage, learn: the doses' strategy");
  app.add_option("--dose", a.dose,
                 "raw samples: send `dose G` (G grams, or `auto`: the fill the recording reached) when the recorded "
                 "valve opened");
  app.add_option("--send", a.send, "raw samples: a console line, sent once the previous command has finished (repeatable)");
  app.add_option("--at", a.at, "raw samples: jiffy of the first console line (default: when the recorded valve opened)")
      ->check(CLI::Range(0L, 100'000'000L));
  app.add_option("--csv", a.csv,
                 "per jiffy: t_s,jiffy,raw,gross_g,filtered_g,prediction_g,valve,state,recorded_valve");
  app.add_option("--console-out", a.console_out, "write the indicator's console output to this file");
  app.add_option("--scene", a.scene, "raw samples: calibrate as the indicator of this scene's plant")->capture_default_str();
  app.add_option("--seed", a.seed, "raw samples: seed of that plant (its calibration)")->capture_default_str();
  app.add_option("--nvm", a.nvm, "raw samples: calibration and parameters from a dynweigh-fw --nvm file");
  app.add_option("--zero-counts", a.zero_counts, "raw samples: counts of the empty scale")
      ->check(FiniteRange(double(INT32_MIN), double(INT32_MAX)));
  app.add_option("--counts-per-gram", a.counts_per_gram, "raw samples: span")->check(FiniteRange(1e-6, 1e6));
  app.add_flag("-q,--quiet", a.quiet, "no progress bar, no open-loop notice");
  if (const auto exit_status = tools::parse_command_line(app, argc, argv, "dynweigh replay")) return *exit_status;
  try {
    return run(a);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dynweigh replay: %s\n", e.what());
    return 1;
  }
}

}  // namespace dynweigh::tools
