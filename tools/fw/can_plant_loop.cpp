#include "can_plant_loop.hpp"

#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>

#include "dynweigh/hal/can/protocol.hpp"
#include "dynweigh/hal/host/file_settings_store.hpp"
#include "dynweigh/hal/host/pty_console.hpp"
#include "dynweigh/hal/host/scripted_console.hpp"
#include "dynweigh/hal/host/simulated_plant_ports.hpp"
#include "dynweigh/hal/linux/can_board.hpp"
#include "dynweigh/sim/plant.hpp"
#include "dynweigh/sim/scene.hpp"

namespace dynweigh::tools {
namespace {

using hal::linux_can::CanBoard;

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

// Without --nvm (or with an empty one) the indicator starts with the factory calibration of the
// default scene's load cell, the one `dynweigh plant` simulates; a real scale needs `zero`/`cal`.
firmware::PersistentSettings initial_settings(hal::host::FileSettingsStore* store) {
  firmware::PersistentSettings settings;
  if (store && store->load(settings)) return settings;
  const sim::Plant reference(sim::default_scene(), 1);
  settings = hal::host::factory_settings(reference);
  if (store) store->save(settings);
  return settings;
}

class CsvTrace {
 public:
  explicit CsvTrace(const std::string& path) : file_(std::fopen(path.c_str(), "w")) {
    if (!file_) throw std::runtime_error("cannot create " + path);
    std::fprintf(file_, "t_s,jiffy,static_kg,in_flight_kg,force_n,raw,filtered_g,valve\n");
  }
  ~CsvTrace() { std::fclose(file_); }
  CsvTrace(const CsvTrace&) = delete;
  CsvTrace& operator=(const CsvTrace&) = delete;
  // The plant's truth is not known with an external plant: its columns stay empty (SPEC §5).
  void write(std::uint32_t jiffy, const firmware::Indicator& indicator, const firmware::Outputs& out, std::int32_t raw) {
    std::fprintf(file_, "%.2f,%u,,,,%d,%.1f,%d\n", jiffy * 0.01, jiffy, raw, double(indicator.filtered_weight_g()),
                 static_cast<int>(out.valve));
  }

 private:
  std::FILE* file_;
};

}  // namespace

int run_can_plant(const CanPlantOptions& options) {
  std::unique_ptr<hal::host::FileSettingsStore> store;
  if (!options.nvm.empty()) store = std::make_unique<hal::host::FileSettingsStore>(options.nvm);
  firmware::Indicator indicator(initial_settings(store.get()));
  const std::unique_ptr<hal::linux_can::CanTransport> link = hal::linux_can::open_can_transport(options.transport);
  std::unique_ptr<CsvTrace> csv;
  if (!options.csv.empty()) csv = std::make_unique<CsvTrace>(options.csv);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::signal(SIGPIPE, SIG_IGN);

  if (options.console == "pty") {
    hal::host::PtyConsole console;
    std::printf("console=%s\n", console.device_path().c_str());
    std::fflush(stdout);
    CanBoard board(*link, indicator, console, store.get(), options.realtime);
    board.send_heartbeat(hal::can::kNmtBootUp);
    while (!g_stop) {
      const CanBoard::Event event = board.poll(100);
      if (event == CanBoard::Event::closed) throw std::runtime_error(link->name() + " closed");
      // A plant that stops is not fatal here: the console stays up for the next one.
    }
    board.send_heartbeat(hal::can::kNmtStopped);
    return 0;
  }

  hal::host::ScriptedConsole console(
      [](std::string& line) { return bool(std::getline(std::cin, line)); },
      [](const char* data, std::size_t n) {
        std::fwrite(data, 1, n, stdout);
        std::fflush(stdout);
      });
  CanBoard board(*link, indicator, console, store.get(), options.realtime);
  board.send_heartbeat(hal::can::kNmtBootUp);
  while (!g_stop) {
    const CanBoard::Event event = board.poll(100);
    if (event == CanBoard::Event::closed) {
      std::fprintf(stderr, "dynweigh-fw: %s closed\n", link->name().c_str());
      return 1;
    }
    if (event == CanBoard::Event::plant_stopped) {
      if (console.input_ended() && !board.last_outputs().busy) break;
      std::fprintf(stderr, "dynweigh-fw: the plant stopped (load-cell heartbeat: stopped) at jiffy %u\n", board.jiffy());
      return 1;
    }
    if (event == CanBoard::Event::quiet) continue;
    const firmware::Outputs& out = board.last_outputs();
    if (csv) csv->write(board.jiffy() - 1, indicator, out, board.last_raw_counts());
    console.set_indicator_busy(out.busy);
    if (console.input_ended() && !out.busy) break;
  }
  // Tell the plant this indicator is leaving (CiA 301 heartbeat, NMT state stopped).
  board.send_heartbeat(hal::can::kNmtStopped);
  return 0;
}

}  // namespace dynweigh::tools
