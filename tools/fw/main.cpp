// dynweigh-fw: the indicator firmware on a host, against the in-process plant or a plant on CAN
// (docs/programs.md).
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "dynweigh/hal/host/file_settings_store.hpp"
#include "dynweigh/hal/host/host_clock.hpp"
#include "dynweigh/hal/host/inputs_recording.hpp"
#include "dynweigh/hal/host/lockstep_session.hpp"
#include "dynweigh/hal/host/scripted_console.hpp"
#include "dynweigh/hal/host/stream_line_reader.hpp"
#include "dynweigh/sim/scene.hpp"
#include "can_plant_loop.hpp"
#include "nvm_start.hpp"
#include "plant_console_command.hpp"
#include "plc_link.hpp"
#include "serial_console.hpp"
#include "stop_signal.hpp"
#include "trace_csv.hpp"
#include "command_line.hpp"

namespace {

using namespace dynweigh;

struct Options {
  std::string plant = "sim:default";
  std::string console = "stdio";
  bool realtime = false;
  std::uint64_t seed = 1;
  std::string csv;
  std::string nvm;
  bool nvm_reset = false;
  std::string record;  // every jiffy's Inputs, for dynweigh replay
  std::string pty_link;
  double plant_timeout_s = 10.0;
  std::vector<std::string> modbus;  // tcp:... / rtu:... endpoints
};

sim::Scene scene_from_plant_option(const std::string& plant) {
  if (plant != "sim" && plant.rfind("sim:", 0) != 0) {
    throw std::runtime_error("--plant must be sim[:<scene>] or can:<transport>, not '" + plant + "'");
  }
  const std::string name = plant.size() > 4 ? plant.substr(4) : "default";
  const auto scene = sim::scene_by_name(name);
  if (!scene) throw std::runtime_error("unknown scene '" + name + "'");
  return *scene;
}

int run(const Options& options) {
  tools::install_stop_handlers();
  tools::PlcLink plc(tools::parse_modbus_options(options.modbus));
  if (options.plant.rfind("can:", 0) == 0) {  // an external plant on a CAN transport (hal/linux)
    return tools::run_can_plant({options.plant.substr(4), options.console, options.realtime, options.csv, options.nvm,
                                 options.nvm_reset, options.pty_link, options.plant_timeout_s, &plc, options.record});
  }
  const sim::Scene scene = scene_from_plant_option(options.plant);
  tools::NvmStart nvm = tools::open_nvm(options.nvm, options.nvm_reset);
  hal::host::LockstepSession session(scene, options.seed, nvm.stored, nvm.store.get());
  tools::save_starting_settings(nvm, options.nvm, session.indicator().settings());
  std::unique_ptr<tools::TraceCsv> csv;
  // --record: every jiffy's record (Inputs, Outputs, console bytes) written for dynweigh replay.
  std::unique_ptr<hal::host::InputsRecordingWriter> recording;
  if (!options.record.empty()) {
    recording = std::make_unique<hal::host::InputsRecordingWriter>(
        options.record, session.indicator(),
        "dynweigh-fw --plant " + options.plant + " --seed " + std::to_string(options.seed));
    session.record_to(recording.get());
  }
  const auto step = [&](hal::ConsolePort& port) { return session.step(port); };
  if (!options.csv.empty()) csv = std::make_unique<tools::TraceCsv>(options.csv);
  hal::host::HostClock clock(options.realtime);

  // A serial line (a pty we make, or a device): idle and silent, the plant follows the wall clock;
  // busy, it runs ahead in lockstep unless --realtime.
  // SIGINT or SIGTERM ends a serial console's loop (the pty link goes with it).
  // With --modbus the PLC's commands join the console's (plc_link.hpp).
  tools::JiffyStopwatch& stopwatch = plc.stopwatch();
  const auto serve = [&](auto& console) {
    hal::ConsolePort& port = plc.attach(console);
    for (bool busy = false; !tools::stop_requested();) {
      if (!busy && !options.realtime) console.wait_for_input(10);
      stopwatch.start();
      plc.before_jiffy();
      const firmware::Outputs outputs = step(port);
      busy = outputs.busy;
      plc.after_jiffy(session.indicator(), outputs);
      if (csv) csv->write(session.last_row());
      stopwatch.stop();
      clock.wait_next_jiffy();
    }
    return 0;
  };
  if (const std::optional<int> status = tools::serve_on_serial_console(options.console, options.pty_link, serve)) {
    return *status;
  }

  // stdin, read without blocking the loop. In lockstep the plant's time stands still while the
  // indicator is idle and no line has come (the loop waits on stdin, but a signal ends the wait);
  // in real time the plant goes on and stdin is only polled. With --modbus a PLC command is work
  // too: the idle loop looks for a line or a command every 10 ms, and the end of stdin ends
  // nothing (a signal does).
  hal::host::StreamLineReader lines(STDIN_FILENO, tools::stop_requested);
  const bool lockstep_idle_waits = !options.realtime && plc.active();
  std::optional<std::string> early_line;  // a line the idle wait brought, for the next jiffy
  bool input_ended = false;
  const auto next_line = [&](std::string& line) {
        if (early_line) {
          line = *early_line;
          early_line.reset();
          return hal::host::ScriptedConsole::Poll::line;
        }
        if (input_ended) return hal::host::ScriptedConsole::Poll::ended;
        switch (lines.next(line, options.realtime || plc.active() ? 0 : -1)) {
          case hal::host::StreamLineReader::Result::line: return hal::host::ScriptedConsole::Poll::line;
          case hal::host::StreamLineReader::Result::nothing_yet: return hal::host::ScriptedConsole::Poll::nothing_yet;
          case hal::host::StreamLineReader::Result::ended: break;
        }
        input_ended = true;
        return hal::host::ScriptedConsole::Poll::ended;
      };
  // A `plant ...` line is answered by the simulated plant at once; the indicator never sees it.
  hal::host::ScriptedConsole console(
      [&](std::string& line) {
        for (;;) {
          const hal::host::ScriptedConsole::Poll got = next_line(line);
          std::string answer;
          if (got != hal::host::ScriptedConsole::Poll::line ||
              !tools::answer_plant_command(line, session.plant(), answer)) {
            return got;
          }
          std::fwrite(answer.data(), 1, answer.size(), stdout);
          std::fflush(stdout);
        }
      },
      [](const char* data, std::size_t n) {
        std::fwrite(data, 1, n, stdout);
        std::fflush(stdout);
      });
  hal::ConsolePort& port = plc.attach(console);
  bool busy = false;
  while (!tools::stop_requested()) {
    if (lockstep_idle_waits && !busy && !early_line && !plc.command_waiting()) {
      std::string line;
      const auto got = input_ended ? hal::host::StreamLineReader::Result::ended : lines.next(line, 10);
      if (got == hal::host::StreamLineReader::Result::line) {
        early_line = line;
      } else {
        if (got == hal::host::StreamLineReader::Result::ended) {
          input_ended = true;
          std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        if (!plc.command_waiting()) continue;
      }
    }
    stopwatch.start();
    plc.before_jiffy();
    const firmware::Outputs outputs = step(port);
    plc.after_jiffy(session.indicator(), outputs);
    if (csv) csv->write(session.last_row());
    stopwatch.stop();
    busy = outputs.busy;
    console.set_indicator_busy(outputs.busy);
    if (console.input_ended() && !outputs.busy && !plc.active()) return 0;
    clock.wait_next_jiffy();
  }
  return 128 + tools::stop_signal();
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  CLI::App app{"dynweigh-fw: the dynweigh weigh-indicator firmware on a host, against a simulated plant.\n"
               "Commands are read from the console (see `help`); with --console stdio each line is sent\n"
               "once the previous command has finished, and the program exits 0 at end of input."};
  app.set_version_flag("--version", "dynweigh-fw " DYNWEIGH_VERSION, "print the version and exit");
  app.add_option("--plant", options.plant, "sim[:<scene>] (in-process plant, lockstep) or can:<transport>")
      ->capture_default_str();
  app.add_option("--console", options.console,
                 "stdio, pty (prints console=<device>) or a serial device; pty and devices answer in CR LF")
      ->check(CLI::IsMember({"stdio", "pty"}) | CLI::ExistingPath)
      ->capture_default_str();
  app.add_flag("--realtime", options.realtime, "pace jiffies at 10 ms of wall time")->disable_flag_override();
  app.add_option("--seed", options.seed, "seed of the plant's disturbances")->check(
      [](const std::string& text) -> std::string {
        const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
        return digits ? "" : "must be a whole number, 0 or more";
      })->capture_default_str();
  app.add_option("--csv", options.csv, "write one row per jiffy: plant truth beside the firmware's view");
  app.add_option("--nvm", options.nvm,
                 "keep calibration and parameters in this file (created if absent; a path that cannot be "
                 "written is refused)");
  app.add_flag("--nvm-reset", options.nvm_reset, "start from defaults, erasing what the --nvm file holds");
  app.add_option("--pty-link", options.pty_link,
                 "with --console pty: a symlink PATH to the pty's device, removed at exit");
  app.add_option("--plant-timeout", options.plant_timeout_s,
                 "--plant can: in lockstep, give up with exit status 3 when no load-cell sample came in this "
                 "many seconds (0: wait for ever)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--modbus", options.modbus,
                 "serve a PLC: tcp:<host>:<port> (Modbus TCP) or rtu:<device>:<baud>:<8N1|8E1|8O1>:<unit id> "
                 "(Modbus RTU); may be given twice (TCP and RTU at once). The register map is in "
                 "docs/plc-modbus.md. With --modbus the end of stdin does not end the program; SIGINT or SIGTERM "
                 "does, printing modbus_requests= and the loop's jiffy timing (loop_jiffy_worst_us=) on stderr")
      ->check([](const std::string& text) {
        std::string error;
        return modbus::parse_endpoint(text, error) ? std::string() : error;
      });
  app.add_option("--record", options.record, "record every jiffy (inputs, outputs, console bytes) for dynweigh replay, with either plant");
  if (const auto exit_status = tools::parse_command_line(app, argc, argv, "dynweigh-fw")) return *exit_status;
  if (options.nvm_reset && options.nvm.empty()) {
    std::fprintf(stderr, "dynweigh-fw: --nvm-reset needs --nvm FILE\n");
    return 2;
  }
  if (!options.pty_link.empty() && options.console != "pty") {
    std::fprintf(stderr, "dynweigh-fw: --pty-link works with --console pty only\n");
    return 2;
  }
  try {
    return run(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dynweigh-fw: %s\n", e.what());
    return 1;
  }
}
