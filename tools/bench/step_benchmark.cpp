#include "step_benchmark.hpp"

#include <benchmark/benchmark.h>

#include <memory>
#include <vector>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/hal/host/simulated_plant_ports.hpp"
#include "dynweigh/sim/plant.hpp"

namespace dynweigh::tools {
namespace {

// Recorded inputs of a real dose (default scene), so the benchmark times the firmware alone.
std::vector<firmware::LoadCellInput> recorded_dose_samples() {
  sim::Plant plant(sim::default_scene(), 1);
  plant.command_valve(sim::ValveCommand::open);
  std::vector<firmware::LoadCellInput> samples;
  for (int j = 0; j < 600; ++j) {
    const sim::LoadCellSample s = plant.sample();
    samples.push_back({s.raw_counts, s.counter, s.status, true});
    plant.advance(0.01);
  }
  return samples;
}

void IndicatorStepWhileDosing(benchmark::State& state) {
  const sim::Plant plant(sim::default_scene(), 1);
  const firmware::PersistentSettings settings = hal::host::factory_settings(plant);
  const auto samples = recorded_dose_samples();
  auto indicator = std::make_unique<firmware::Indicator>(settings);
  const char command[] = "dose 40000\n";  // a target the recording never reaches: dosing throughout
  std::size_t index = 0;
  firmware::Inputs inputs;
  char sink[256];
  for (auto _ : state) {
    if (index == samples.size()) {
      state.PauseTiming();
      indicator = std::make_unique<firmware::Indicator>(settings);
      index = 0;
      state.ResumeTiming();
    }
    inputs.jiffy = std::uint32_t(index);
    inputs.load_cell = samples[index];
    inputs.console_rx = index == 0 ? command : nullptr;
    inputs.console_rx_length = index == 0 ? sizeof command - 1 : 0;
    benchmark::DoNotOptimize(indicator->step(inputs));
    indicator->drain_console(sink, sizeof sink);
    ++index;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(IndicatorStepWhileDosing);

}  // namespace

int run_step_benchmark(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace dynweigh::tools
