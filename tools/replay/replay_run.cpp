#include "replay_run.hpp"

#include <algorithm>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/hal/host/inputs_recording.hpp"

namespace dynweigh::tools {
namespace {

using hal::host::RecordedJiffy;

// One indicator, stepped jiffy by jiffy, watched for what a reader of the replay wants to know.
class ReplayStepper {
 public:
  // `last_sequence`: the live board's newest result number, so RESULT lines are numbered as they were.
  ReplayStepper(const firmware::PersistentSettings& settings, const ReplaySinks& sinks, ReplaySummary& summary,
                std::uint32_t last_sequence = 0)
      : indicator_(std::make_unique<firmware::Indicator>(settings)), sinks_(sinks), summary_(summary) {
    indicator_->resume_sequence(last_sequence);
  }

  // Steps one jiffy; `recorded_valve` is what the recording's valve did (-1 unknown). The console
  // is drained of `drain` bytes at most: as many as the live board sent (a serial line takes what
  // it has room for, and what stays in the indicator's ring holds the next command back).
  firmware::Outputs step(const RecordedJiffy& jiffy, int recorded_valve,
                         std::size_t drain = static_cast<std::size_t>(-1)) {
    const firmware::Outputs out = indicator_->step(jiffy.inputs());
    busy_ = out.busy;
    tx_.clear();
    char buffer[512];
    for (std::size_t n; tx_.size() < drain &&
                        (n = indicator_->drain_console(buffer, std::min(sizeof buffer, drain - tx_.size()))) > 0;) {
      tx_.append(buffer, n);
    }
    if (!tx_.empty() && sinks_.console) sinks_.console(tx_.data(), tx_.size());
    collect_results();

    const bool dosing = out.state == firmware::IndicatorState::dosing;
    if (dosing && !was_dosing_ && summary_.dose_start_jiffy < 0) summary_.dose_start_jiffy = long(jiffy.jiffy);
    // A cutoff: the valve told to close while the dose goes on (settling), not by a fault.
    if (was_dosing_ && previous_valve_ != firmware::ValveCommand::closed && out.valve == firmware::ValveCommand::closed &&
        out.state != firmware::IndicatorState::fault && summary_.cutoff_jiffy < 0) {
      summary_.cutoff_jiffy = long(jiffy.jiffy);
    }
    was_dosing_ = dosing;
    previous_valve_ = out.valve;

    if (sinks_.row) {
      const firmware::Calibration& cal = indicator_->settings().calibration;
      ReplayRow row;
      row.jiffy = jiffy.jiffy;
      row.raw_counts = jiffy.load_cell.raw_counts;
      row.gross_g = cal.valid() ? cal.counts_above_zero(row.raw_counts) / cal.counts_per_gram : 0.0f;
      row.filtered_g = out.filtered_g;
      row.has_prediction = dosing;
      row.prediction_g = out.predicted_g;
      row.valve = out.valve;
      row.state = out.state;
      row.recorded_valve = recorded_valve;
      sinks_.row(row);
    }
    ++summary_.jiffies;
    return out;
  }

  const std::string& console_tx() const { return tx_; }
  // What is left in the indicator's console, to the console sink.
  void drain_rest() {
    tx_.clear();
    char buffer[512];
    for (std::size_t n; (n = indicator_->drain_console(buffer, sizeof buffer)) > 0;) tx_.append(buffer, n);
    if (!tx_.empty() && sinks_.console) sinks_.console(tx_.data(), tx_.size());
    collect_results();
  }
  bool busy() const { return busy_; }
  // The ERR answers printed since the last call.
  std::vector<std::string> take_errors() { return std::exchange(errors_, {}); }

 private:
  void collect_results() {
    pending_line_ += tx_;
    for (std::size_t end; (end = pending_line_.find('\n')) != std::string::npos;) {
      const std::string line = pending_line_.substr(0, end);
      if (line.rfind("RESULT ", 0) == 0) summary_.results.push_back(line);
      if (line.rfind("ERR", 0) == 0) errors_.push_back(line.back() == '\r' ? line.substr(0, line.size() - 1) : line);
      pending_line_.erase(0, end + 1);
    }
  }

  std::unique_ptr<firmware::Indicator> indicator_;  // a few kB: keep it off the stack
  const ReplaySinks& sinks_;
  ReplaySummary& summary_;
  std::string tx_, pending_line_;
  std::vector<std::string> errors_;
  bool was_dosing_ = false;
  bool busy_ = false;
  firmware::ValveCommand previous_valve_ = firmware::ValveCommand::closed;
};

// Rewrites `dose <g> [<strategy>]` lines of a console stream to another strategy. Bytes of a line
// wait until its end has arrived, so a line split over jiffies is rewritten whole.
class DoseStrategyRewriter {
 public:
  explicit DoseStrategyRewriter(firmware::DosingStrategy strategy) : name_(firmware::strategy_name(strategy)) {}

  std::string feed(const std::string& bytes) {
    std::string out;
    for (char c : bytes) {
      if (c != '\r' && c != '\n') {
        line_.push_back(c);
        continue;
      }
      out += rewrite(line_);
      out.push_back(c);
      line_.clear();
    }
    return out;
  }
  std::size_t rewritten() const { return rewritten_; }

 private:
  std::string rewrite(const std::string& line) {
    std::istringstream words(line);
    std::string command, grams, extra;
    if (!(words >> command) || command != "dose" || !(words >> grams)) return line;
    ++rewritten_;
    return "dose " + grams + " " + name_;
  }

  std::string name_;
  std::string line_;
  std::size_t rewritten_ = 0;
};

std::string describe(const firmware::Outputs& o, bool telemetry) {
  std::ostringstream s;
  s << "valve=" << int(o.valve) << " delay=" << int(o.valve_delay_100us) << " state=" << int(o.state)
    << " weight_100mg=" << o.weight_100mg << " busy=" << o.busy;
  if (telemetry) {
    s.precision(9);
    s << " filtered_g=" << o.filtered_g << " net_g=" << o.net_g << " predicted_g=" << o.predicted_g
      << " fault=" << firmware::fault_name(o.fault);
  }
  return s.str();
}

}  // namespace

ReplaySummary replay_inputs_recording(const std::string& path, const ReplayOptions& options, const ReplaySinks& sinks) {
  if (!options.console_lines.empty()) {
    throw std::runtime_error("an inputs recording replays its own console; --dose/--send are for raw samples");
  }
  hal::host::InputsRecordingReader reader(path);
  ReplaySummary summary;
  summary.format = "inputs";
  summary.source = reader.source();
  summary.open_loop = options.strategy.has_value();
  std::optional<DoseStrategyRewriter> rewriter;
  if (options.strategy) rewriter.emplace(*options.strategy);
  ReplayStepper stepper(reader.settings(), sinks, summary, reader.last_sequence());
  summary.checked = !summary.open_loop;
  for (RecordedJiffy jiffy; reader.next(jiffy);) {
    if (rewriter) jiffy.console_rx = rewriter->feed(jiffy.console_rx);
    const int recorded_valve = jiffy.has_outputs ? int(jiffy.outputs.valve) : -1;
    // While the replay matches, the console drains as it did live; open loop, or once it has
    // differed, all of it (what this build says differently must still be shown in full).
    const bool matching = jiffy.has_outputs && summary.checked && summary.first_mismatch_jiffy < 0;
    const std::size_t drain = matching ? jiffy.console_tx.size() : static_cast<std::size_t>(-1);
    const firmware::Outputs out = stepper.step(jiffy, recorded_valve, drain);
    if (!jiffy.has_outputs) summary.checked = false;
    if (summary.checked && summary.first_mismatch_jiffy < 0) {
      if (!hal::host::same_outputs(out, jiffy.outputs, jiffy.has_telemetry)) {
        summary.first_mismatch_jiffy = long(jiffy.jiffy);
        summary.mismatch = "outputs " + describe(out, jiffy.has_telemetry) + ", recorded " +
                           describe(jiffy.outputs, jiffy.has_telemetry);
      } else if (stepper.console_tx() != jiffy.console_tx) {
        summary.first_mismatch_jiffy = long(jiffy.jiffy);
        summary.mismatch = "console output differs";
      }
    }
    if (sinks.progress) sinks.progress(summary.jiffies, 0);
  }
  // A replay that differed shows all it said; one that matched, only what the live board sent.
  if (!summary.checked || summary.first_mismatch_jiffy >= 0) stepper.drain_rest();
  if (rewriter) summary.doses_rewritten = rewriter->rewritten();
  return summary;
}

ReplaySummary replay_samples(const RecordedSamples& samples, const ReplayOptions& options, const ReplaySinks& sinks) {
  ReplaySummary summary;
  summary.format = samples.format;
  summary.open_loop = true;
  if (options.strategy) throw std::runtime_error("--strategy applies to an inputs recording; give --dose G --strategy S together");
  const long start = options.start_jiffy >= 0 ? options.start_jiffy : std::max(0L, samples.first_open_jiffy());
  ReplayStepper stepper(options.settings, sinks, summary);
  std::size_t next_line = 0;
  bool waiting = false;  // a line was sent; the indicator has not yet finished it
  for (std::size_t i = 0; i < samples.samples.size(); ++i) {
    RecordedJiffy jiffy;
    jiffy.jiffy = std::uint32_t(i);
    jiffy.load_cell.raw_counts = samples.samples[i].raw_counts;
    jiffy.load_cell.counter = std::uint16_t(i & 0xffffu);
    const int valve = samples.samples[i].valve;
    // The feedback a valve module would have sent: as recorded, open = 3, half = 2 (docs/can-protocol.md).
    jiffy.valve_position = valve == 2   ? firmware::ValvePosition::open
                           : valve == 1 ? firmware::ValvePosition::half
                                        : firmware::ValvePosition::closed;
    if (!waiting && next_line < options.console_lines.size() && long(i) >= start) {
      jiffy.console_rx = options.console_lines[next_line++] + "\n";
      ++summary.commands_sent;
      waiting = true;
    }
    stepper.step(jiffy, valve);
    for (const std::string& error : stepper.take_errors()) {
      const std::string sent = next_line > 0 ? "'" + options.console_lines[next_line - 1] + "'" : "(nothing sent)";
      summary.refusals.push_back(sent + ": " + error);
    }
    if (waiting && !stepper.busy()) waiting = false;
    if (sinks.progress) sinks.progress(i + 1, samples.samples.size());
  }
  summary.unsent.assign(options.console_lines.begin() + std::ptrdiff_t(next_line), options.console_lines.end());
  return summary;
}

}  // namespace dynweigh::tools
