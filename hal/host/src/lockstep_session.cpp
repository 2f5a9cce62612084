#include "dynweigh/hal/host/lockstep_session.hpp"

namespace dynweigh::hal::host {

LockstepSession::LockstepSession(const sim::Scene& scene, std::uint64_t seed,
                                 std::optional<firmware::PersistentSettings> settings, SettingsStore* store)
    : plant_(scene, seed),
      load_cell_(plant_),
      valve_(plant_, kJiffyS),
      gate_(plant_),
      ingredients_(plant_, kJiffyS),
      indicator_(settings ? *settings : factory_settings(plant_)),
      store_(store) {
  indicator_.attach_logbook(store && store->logbook() ? store->logbook() : &ram_logbook_.logbook());
  indicator_.attach_totalizers(store ? store->totalizers() : nullptr);
}

firmware::Outputs LockstepSession::step(ConsolePort& console) {
  const sim::PlantTruth truth = plant_.truth();  // at the instant the sample is taken
  Ports ports{load_cell_, valve_, console, store_, save_report_, nullptr, recorder_, &gate_, &ingredients_};
  record_ = run_one_jiffy(indicator_, ports, jiffy_);
  save_report_ = ports.save_report;
  row_ = TraceRow{truth.time_s, jiffy_, truth.static_kg, truth.in_flight_kg, truth.force_n,
                  record_.load_cell.raw_counts, double(record_.outputs.filtered_g),
                  static_cast<int>(record_.outputs.valve)};
  plant_.advance(kJiffyS);
  ++jiffy_;
  return record_.outputs;
}

}  // namespace dynweigh::hal::host
