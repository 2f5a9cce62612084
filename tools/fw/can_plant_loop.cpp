#include "can_plant_loop.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>

#include "dynweigh/hal/can/protocol.hpp"
#include "dynweigh/hal/host/file_settings_store.hpp"
#include "dynweigh/hal/host/inputs_recording.hpp"
#include "dynweigh/hal/host/lockstep_session.hpp"
#include "dynweigh/hal/host/scripted_console.hpp"
#include "dynweigh/hal/host/simulated_plant_ports.hpp"
#include "dynweigh/hal/host/stream_line_reader.hpp"
#include "dynweigh/hal/linux/can_board.hpp"
#include "dynweigh/sim/plant.hpp"
#include "dynweigh/sim/scene.hpp"
#include "nvm_start.hpp"
#include "plc_link.hpp"
#include "serial_console.hpp"
#include "stop_signal.hpp"

namespace dynweigh::tools {
namespace {

using hal::linux_can::CanBoard;

// What the indicator starts with, said on stderr. Without --nvm: the factory calibration of the
// default scene's load cell, the one `dynweigh plant` simulates, so the pair works out of the box and
// nothing persists. With a new (or erased, or unreadable) --nvm file: no calibration at all, as a
// new indicator on a real installation, commissioned with `zero`, a test weight and `cal <g>`.
firmware::PersistentSettings initial_settings(NvmStart& nvm, const std::string& path) {
  if (nvm.stored) {
    if (nvm.stored->calibration.valid()) {
      std::fprintf(stderr, "dynweigh-fw: calibration: from --nvm %s\n", path.c_str());
    } else {
      std::fprintf(stderr, "dynweigh-fw: calibration: none in --nvm %s yet: commission with zero, a test weight and cal <g>\n",
                   path.c_str());
    }
    return *nvm.stored;
  }
  if (nvm.store) {
    const firmware::PersistentSettings blank;
    save_starting_settings(nvm, path, blank);
    std::fprintf(stderr,
                 "dynweigh-fw: calibration: none (new --nvm %s): commission with zero, a test weight and cal <g>\n",
                 path.c_str());
    return blank;
  }
  std::fprintf(stderr,
               "dynweigh-fw: calibration: the default scene's factory calibration (no --nvm; `dynweigh plant`'s "
               "load cell)\n");
  const sim::Plant reference(sim::default_scene(), 1);
  return hal::host::factory_settings(reference);
}

// Lockstep: the plant must send the first sample. Says what the board waits for, and gives up
// after the timeout; a plant that was heard and went away is no reason to stop.
class FirstSampleWatch {
 public:
  FirstSampleWatch(const std::string& link, double timeout_s, bool realtime)
      : timeout_s_(realtime ? 0.0 : timeout_s), start_(std::chrono::steady_clock::now()) {
    std::fprintf(stderr, "dynweigh-fw: waiting for the load cell's samples (CAN 0x190) on %s%s\n", link.c_str(),
                 realtime ? "" : timeout_s > 0 ? " (lockstep: the plant sends first)" : " (lockstep, no time limit)");
  }
  // True when the wait is over without a sample.
  bool expired(const CanBoard& board) const {
    if (timeout_s_ <= 0 || board.jiffy() > 0) return false;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count() >= timeout_s_;
  }
  int fail(const std::string& link) const {
    std::fprintf(stderr,
                 "dynweigh-fw: no load-cell sample (CAN 0x190) on %s in %g s: is the plant running and sending to "
                 "this port? (--plant-timeout)\n",
                 link.c_str(), timeout_s_);
    return kExitNoPlant;
  }

 private:
  double timeout_s_;
  std::chrono::steady_clock::time_point start_;
};

class CsvTrace {
 public:
  explicit CsvTrace(const std::string& path) : file_(std::fopen(path.c_str(), "w")) {
    if (!file_) throw std::runtime_error("cannot create " + path);
    std::fprintf(file_, "t_s,jiffy,static_kg,in_flight_kg,force_n,raw,filtered_g,valve\n");
  }
  ~CsvTrace() { std::fclose(file_); }
  CsvTrace(const CsvTrace&) = delete;
  CsvTrace& operator=(const CsvTrace&) = delete;
  // The plant's truth is not known with an external plant: its columns stay empty (docs/programs.md).
  void write(const hal::JiffyRecord& jiffy) {
    std::fprintf(file_, "%.2f,%u,,,,%d,%.1f,%d\n", jiffy.jiffy * 0.01, jiffy.jiffy, jiffy.load_cell.raw_counts,
                 double(jiffy.outputs.filtered_g), static_cast<int>(jiffy.outputs.valve));
  }

 private:
  std::FILE* file_;
};

}  // namespace

int run_can_plant(const CanPlantOptions& options) {
  NvmStart nvm = open_nvm(options.nvm, options.nvm_reset);
  firmware::Indicator indicator(initial_settings(nvm, options.nvm));
  // Without --nvm the results since start-up, in RAM (as the in-process board keeps them).
  auto ram_logbook = std::make_unique<firmware::RamLogbook<hal::host::LockstepSession::kRamLogbookSlots>>();
  indicator.attach_logbook(nvm.store ? nvm.store->logbook() : &ram_logbook->logbook());
  indicator.attach_totalizers(nvm.store ? nvm.store->totalizers() : nullptr);
  const std::unique_ptr<hal::linux_can::CanTransport> link = hal::linux_can::open_can_transport(options.transport);
  std::unique_ptr<CsvTrace> csv;
  if (!options.csv.empty()) csv = std::make_unique<CsvTrace>(options.csv);
  std::unique_ptr<hal::host::InputsRecordingWriter> recording;
  if (!options.record.empty()) {
    recording = std::make_unique<hal::host::InputsRecordingWriter>(options.record, indicator,
                                                                   "dynweigh-fw --plant can:" + options.transport);
  }
  const FirstSampleWatch first_sample(link->name(), options.plant_timeout_s, options.realtime);

  // A serial console (a pty we make, or a device): the board serves it until a signal stops it.
  PlcLink no_plc({});
  PlcLink& plc = options.plc ? *options.plc : no_plc;
  const auto ran_a_jiffy = [](CanBoard::Event event) {
    return event == CanBoard::Event::jiffy || event == CanBoard::Event::stale_jiffy ||
           event == CanBoard::Event::bus_off;
  };
  const auto serve = [&](hal::ConsolePort& console) {
    CanBoard board(*link, indicator, plc.attach(console), nvm.store.get(), options.realtime);
    board.record_to(recording.get());
    board.send_heartbeat(hal::can::kNmtBootUp);
    while (!stop_requested()) {
      plc.before_jiffy();
      const CanBoard::Event event = board.poll(100);
      if (event == CanBoard::Event::closed) throw std::runtime_error(link->name() + " closed");
      if (ran_a_jiffy(event)) plc.after_jiffy(indicator, board.last_outputs());
      if (first_sample.expired(board)) return first_sample.fail(link->name());
      // A plant that stops is not fatal here: the console stays up for the next one.
    }
    board.leave();
    return 0;
  };
  if (const std::optional<int> status = serve_on_serial_console(options.console, options.pty_link, serve)) {
    return *status;
  }

  // stdin is polled, never waited on: every sample gets its 0x220 whether or not a line has come.
  hal::host::StreamLineReader lines(STDIN_FILENO);
  hal::host::ScriptedConsole console(
      [&](std::string& line) {
        switch (lines.next(line, 0)) {
          case hal::host::StreamLineReader::Result::line: return hal::host::ScriptedConsole::Poll::line;
          case hal::host::StreamLineReader::Result::nothing_yet: return hal::host::ScriptedConsole::Poll::nothing_yet;
          case hal::host::StreamLineReader::Result::ended: break;
        }
        return hal::host::ScriptedConsole::Poll::ended;
      },
      [](const char* data, std::size_t n) {
        std::fwrite(data, 1, n, stdout);
        std::fflush(stdout);
      });
  CanBoard board(*link, indicator, plc.attach(console), nvm.store.get(), options.realtime);
  board.record_to(recording.get());
  board.send_heartbeat(hal::can::kNmtBootUp);
  while (!stop_requested()) {
    plc.before_jiffy();
    const CanBoard::Event event = board.poll(100);
    if (ran_a_jiffy(event)) plc.after_jiffy(indicator, board.last_outputs());
    if (event == CanBoard::Event::closed) {
      std::fprintf(stderr, "dynweigh-fw: %s closed\n", link->name().c_str());
      return 1;
    }
    if (first_sample.expired(board)) return first_sample.fail(link->name());
    if (event == CanBoard::Event::plant_stopped) {
      if (console.input_ended() && !board.last_outputs().busy && !plc.active()) break;
      std::fprintf(stderr, "dynweigh-fw: the plant stopped (load-cell heartbeat: stopped) at jiffy %u\n", board.jiffy());
      return 1;
    }
    if (event == CanBoard::Event::quiet) continue;
    const firmware::Outputs& out = board.last_outputs();
    if (csv) csv->write(board.last_record());
    console.set_indicator_busy(out.busy);
    if (console.input_ended() && !out.busy && !plc.active()) break;
  }
  // Close a valve left open, and tell the plant this indicator is leaving (CiA 301 heartbeat, NMT stopped).
  board.leave();
  return stop_requested() ? 128 + stop_signal() : 0;
}

}  // namespace dynweigh::tools
