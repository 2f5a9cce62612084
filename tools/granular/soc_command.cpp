// dynweigh soc: BTW sandpile in 1D (thesis slope model), 2D, 3D, or the extended 2D heap.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <string>

#include "command_line.hpp"
#include "dynweigh/granular/avalanche_statistics.hpp"
#include "dynweigh/granular/btw_sandpile.hpp"
#include "dynweigh/granular/extended_heap_2d.hpp"
#include "dynweigh/granular/random.hpp"
#include "dynweigh/granular/sandpile_height_census.hpp"
#include "dynweigh/granular/slope_sandpile_1d.hpp"
#include "granular_commands.hpp"

namespace dynweigh::tools {

using namespace dynweigh::granular;

int run_soc_command(int argc, char** argv) {
  CLI::App app{"SOC sandpile (thesis section 3.2): BTW in 1D (slope model, eqs. 3.1-3.2), 2D, 3D, or the extended 2D heap"};
  int dim = 2;
  int size = 64;
  long long grains = 100000;
  std::string drop = "center";
  unsigned long long seed = 1;
  bool extended = false;
  int critical_slope = 2;
  std::string csv;
  app.add_option("--dim", dim, "lattice dimension")->check(CLI::IsMember({1, 2, 3}));
  app.add_option("--size", size, "side length L (columns for --dim 1 and --extended)")->check(CLI::Range(3, 4096));
  app.add_option("--grains", grains, "grains to add")->check(CLI::Range(1LL, 10000000000LL));
  app.add_option("--drop", drop, "where grains are added")->check(CLI::IsMember({"center", "random"}));
  app.add_option("--seed", seed, "random seed");
  app.add_flag("--extended", extended, "the thesis' extended 2D heap (grain falls until boxed in, fills holes first)");
  app.add_option("--critical-slope", critical_slope, "z_c of the 1D slope model and of the heap")->check(CLI::Range(1, 1000));
  app.add_option("--csv", csv, "write one line per grain: grain,size,area,duration,lost,max_height");
  if (const auto exit_status = tools::parse_command_line(app, argc, argv, "dynweigh soc")) return *exit_status;
  if (extended && dim != 2) return fail("soc", "--extended is the 2D heap; use --dim 2");
  if (dim == 3 && size > 256) return fail("soc", "--size above 256 in 3D needs too much memory");

  std::ofstream out;
  if (!csv.empty()) {
    out.open(csv);
    if (!out) return fail("soc", "cannot write " + csv);
    out << "grain,size,area,duration,lost,max_height\n";
  }
  Random random(seed);
  AvalancheStatistics stationary;  // second half of the run
  const long long stationary_from = grains / 2;
  const bool at_centre = drop == "center";
  double mean_height = 0;
  std::string extra;

  if (extended) {
    ExtendedHeap2d heap(size, critical_slope, HeapEdges::open_floor);
    for (long long g = 0; g < grains; ++g) {
      const int column = at_centre ? heap.centre_column() : static_cast<int>(random.below(static_cast<std::uint64_t>(size)));
      const Avalanche a = heap.add_grain(column, random);
      if (g >= stationary_from) stationary.record(a);
      if (out) out << g << ',' << a.size << ',' << a.area << ',' << a.duration << ',' << a.grains_lost << ',' << heap.max_height() << '\n';
    }
    mean_height = static_cast<double>(heap.total_grains()) / size;
    extra = "max_height=" + std::to_string(heap.max_height()) + "\n";
  } else if (dim == 1) {
    SlopeSandpile1d pile(size, critical_slope);
    for (long long g = 0; g < grains; ++g) {
      const int column = at_centre ? 0 : static_cast<int>(random.below(static_cast<std::uint64_t>(size)));
      const Avalanche a = pile.add_grain(column);
      if (g >= stationary_from) stationary.record(a);
      if (out) out << g << ',' << a.size << ',' << a.area << ',' << a.duration << ',' << a.grains_lost << ',' << pile.height(0) << '\n';
    }
    mean_height = static_cast<double>(pile.total_grains()) / size;
    extra = "max_height=" + std::to_string(pile.height(0)) + "\ncritical_staircase=" + (pile.is_critical_staircase() ? "1" : "0") + "\n";
  } else {
    BtwSandpile pile(dim, size);
    SandpileHeightCensus census(pile, 0 + size / 8);
    const long long census_every = std::max<long long>(1, static_cast<long long>(pile.site_count()) / 16);
    for (long long g = 0; g < grains; ++g) {
      const Avalanche a = at_centre ? pile.add_grain(pile.centre_site()) : pile.add_random_grain(random);
      if (g >= stationary_from) {
        stationary.record(a);
        if ((g - stationary_from) % census_every == 0) census.count(pile);
      }
      if (out) out << g << ',' << a.size << ',' << a.area << ',' << a.duration << ',' << a.grains_lost << ",\n";
    }
    mean_height = census.mean_height();
    for (int h = 0; h < pile.critical_height(); ++h) {
      char line[64];
      std::snprintf(line, sizeof line, "p%d=%.6f\n", h, census.probability(h));
      extra += line;
    }
    extra += "census_samples=" + std::to_string(census.samples()) + "\n";
  }
  std::printf("model=%s\ndim=%d\nsize=%d\ngrains=%lld\ndrop=%s\nmean_height=%.6f\n",
              extended ? "extended_heap" : (dim == 1 ? "slope_1d" : "btw"), dim, size, grains, drop.c_str(), mean_height);
  std::fputs(extra.c_str(), stdout);
  std::printf("mean_topplings=%.6f\nmean_size=%.6f\nmean_area=%.6f\nmean_duration=%.6f\nlargest_size=%lld\ntau_s=%.4f\n",
              stationary.mean_topplings_per_grain(), stationary.mean_size(), stationary.mean_area(),
              stationary.mean_duration(), static_cast<long long>(stationary.largest_size()),
              stationary.estimate_tau_s(4, std::max<std::int64_t>(8, stationary.largest_size() / 8)));
  return 0;
}

}  // namespace dynweigh::tools
