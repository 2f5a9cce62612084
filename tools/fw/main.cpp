// dynweigh-fw: the indicator firmware on a host, against the in-process plant (SPEC §5).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "dynweigh/hal/host/file_settings_store.hpp"
#include "dynweigh/hal/host/host_clock.hpp"
#include "dynweigh/hal/host/inputs_recording.hpp"
#include "dynweigh/hal/host/lockstep_session.hpp"
#include "dynweigh/hal/host/pty_console.hpp"
#include "dynweigh/hal/host/scripted_console.hpp"
#include "dynweigh/hal/host/tty_console.hpp"
#include "dynweigh/sim/scene.hpp"
#include "can_plant_loop.hpp"
#include "trace_csv.hpp"

namespace {

using namespace dynweigh;

struct Options {
  std::string plant = "sim:default";
  std::string console = "stdio";
  bool realtime = false;
  std::uint64_t seed = 1;
  std::string csv;
  std::string nvm;
  std::string record;  // every jiffy's Inputs, for dynweigh replay
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
  if (options.plant.rfind("can:", 0) == 0) {  // an external plant on a CAN transport (hal/linux)
    return tools::run_can_plant({options.plant.substr(4), options.console, options.realtime, options.csv, options.nvm});
  }
  const sim::Scene scene = scene_from_plant_option(options.plant);
  std::unique_ptr<hal::host::FileSettingsStore> store;
  std::optional<firmware::PersistentSettings> stored;
  if (!options.nvm.empty()) {
    store = std::make_unique<hal::host::FileSettingsStore>(options.nvm);
    firmware::PersistentSettings settings;
    if (store->load(settings)) stored = settings;
  }
  hal::host::LockstepSession session(scene, options.seed, stored, store.get());
  if (store && !stored) store->save(session.indicator().settings());
  std::unique_ptr<tools::TraceCsv> csv;
  // --record: the same step, with every jiffy's Inputs and Outputs written for dynweigh replay.
  std::unique_ptr<hal::host::LockstepRecorder> recorder;
  if (!options.record.empty()) {
    recorder = std::make_unique<hal::host::LockstepRecorder>(
        options.record, session, "dynweigh-fw --plant " + options.plant + " --seed " + std::to_string(options.seed));
  }
  const auto step = [&](hal::ConsolePort& port) { return recorder ? recorder->step(port) : session.step(port); };
  if (!options.csv.empty()) csv = std::make_unique<tools::TraceCsv>(options.csv);
  hal::host::HostClock clock(options.realtime);

  // A serial line (a pty we make, or a device): idle and silent, the plant follows the wall clock;
  // busy, it runs ahead in lockstep unless --realtime.
  const auto serve = [&](auto& console) {
    for (bool busy = false;;) {
      if (!busy && !options.realtime) console.wait_for_input(10);
      busy = step(console).busy;
      if (csv) csv->write(session.last_row());
      clock.wait_next_jiffy();
    }
  };
  if (options.console == "pty") {
    hal::host::PtyConsole console;
    std::printf("console=%s\n", console.device_path().c_str());
    std::fflush(stdout);
    serve(console);
  }
  if (options.console != "stdio") {
    hal::host::TtyConsole console(options.console);
    std::printf("console=%s\n", console.device_path().c_str());
    std::fflush(stdout);
    serve(console);
  }

  hal::host::ScriptedConsole console(
      [](std::string& line) { return bool(std::getline(std::cin, line)); },
      [](const char* data, std::size_t n) {
        std::fwrite(data, 1, n, stdout);
        std::fflush(stdout);
      });
  for (;;) {
    const firmware::Outputs outputs = step(console);
    if (csv) csv->write(session.last_row());
    console.set_indicator_busy(outputs.busy);
    if (console.input_ended() && !outputs.busy) return 0;
    clock.wait_next_jiffy();
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  CLI::App app{"dynweigh-fw: the dynweigh weigh-indicator firmware on a host, against a simulated plant.\n"
               "Commands are read from the console (see `help`); with --console stdio each line is sent\n"
               "once the previous command has finished, and the program exits 0 at end of input."};
  app.add_option("--plant", options.plant, "sim[:<scene>] (in-process plant, lockstep) or can:<transport>")
      ->capture_default_str();
  app.add_option("--console", options.console, "stdio or pty (prints console=<device>)")
      ->check(CLI::IsMember({"stdio", "pty"}) | CLI::ExistingPath)
      ->capture_default_str();
  app.add_flag("--realtime", options.realtime, "pace jiffies at 10 ms of wall time");
  app.add_option("--seed", options.seed, "seed of the plant's disturbances")->capture_default_str();
  app.add_option("--csv", options.csv, "write one row per jiffy: plant truth beside the firmware's view");
  app.add_option("--nvm", options.nvm, "keep calibration and parameters in this file");
  app.add_option("--record", options.record, "record every jiffy's inputs (console bytes included) for dynweigh replay");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "dynweigh-fw: %s\n", e.what());
    return 2;
  }
  if (!options.record.empty() && options.plant.rfind("can:", 0) == 0) {
    std::fprintf(stderr, "dynweigh-fw: --record works with --plant sim only\n");
    return 2;
  }
  try {
    return run(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dynweigh-fw: %s\n", e.what());
    return 1;
  }
}
