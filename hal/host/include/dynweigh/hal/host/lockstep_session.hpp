#pragma once
// The host board: an indicator and an in-process plant in lockstep, one plant jiffy per control
// loop iteration. `dynweigh-fw`, the tests and the tools all run dosing cycles through this.
#include <cstdint>
#include <optional>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/firmware/ram_nvm.hpp"
#include "dynweigh/hal/control_loop.hpp"
#include "dynweigh/hal/host/simulated_plant_ports.hpp"
#include "dynweigh/sim/plant.hpp"

namespace dynweigh::hal::host {

// One CSV row (docs/programs.md): the plant's truth beside the firmware's view, at the sample's instant.
struct TraceRow {
  double t_s = 0.0;
  std::uint32_t jiffy = 0;
  double static_kg = 0.0;
  double in_flight_kg = 0.0;
  double force_n = 0.0;
  std::int32_t raw = 0;
  double filtered_g = 0.0;
  int valve = 0;
  bool has_filtered = true;  // false: no firmware ran, the filtered_g column is left empty
};

inline constexpr const char* kTraceHeader = "t_s,jiffy,static_kg,in_flight_kg,force_n,raw,filtered_g,valve";

class LockstepSession {
 public:
  static constexpr double kJiffyS = 0.010;
  // A board without storage keeps its logbook in RAM: the results since it started.
  static constexpr std::size_t kRamLogbookSlots = 129;

  // Without settings the indicator starts calibrated to the plant with default parameters.
  LockstepSession(const sim::Scene& scene, std::uint64_t seed,
                  std::optional<firmware::PersistentSettings> settings = std::nullopt,
                  SettingsStore* store = nullptr);

  firmware::Outputs step(ConsolePort& console);
  // Every jiffy from the next on also goes to `recorder` (nullptr: no more); `dynweigh-fw --record`.
  void record_to(JiffyRecorder* recorder) { recorder_ = recorder; }

  sim::Plant& plant() { return plant_; }
  firmware::Indicator& indicator() { return indicator_; }
  std::uint32_t jiffy() const { return jiffy_; }
  const TraceRow& last_row() const { return row_; }
  // The last jiffy as the indicator saw and decided it.
  const JiffyRecord& last_record() const { return record_; }

 private:
  sim::Plant plant_;
  SimulatedLoadCell load_cell_;
  SimulatedValve valve_;
  SimulatedGate gate_;
  SimulatedIngredientValves ingredients_;
  firmware::Indicator indicator_;
  SettingsStore* store_;
  firmware::RamLogbook<kRamLogbookSlots> ram_logbook_;  // without a store's
  firmware::SettingsSave save_report_ = firmware::SettingsSave::none;  // for the next step
  JiffyRecorder* recorder_ = nullptr;
  JiffyRecord record_;
  std::uint32_t jiffy_ = 0;
  TraceRow row_;
};

}  // namespace dynweigh::hal::host
