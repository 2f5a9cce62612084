// dynweigh plot: CSV -> PNG or SVG with gnuplot. The kind of plot follows the CSV's header:
// - a cycle CSV (dynweigh-fw --csv, dynweigh sim): the thesis' fig. 2.3, the force on the load cell
//   against time with the valve marker, the cutoff, the final static weight, and the phases a reader
//   looks for labelled (impulse step, ramp, rest-drop, ringing); `--replay R.csv` draws the model's
//   prediction from a replay of the same run on it;
// - a replay CSV (dynweigh replay --csv): what the firmware decided: weight, filtered weight, the
//   model's prediction, the valve it commanded beside the valve recorded, the cutoff;
// - a bench CSV (columns strategy, time_ratio, maxdev_g): one Pareto front per strategy, time
//   against worst error, both to be small.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "finite_range.hpp"
#include "output_file.hpp"
#include "command_line.hpp"

namespace dynweigh::tools {
namespace {

constexpr std::size_t kMaxLineLength = 4096;
constexpr std::size_t kMaxRows = 2'000'000;  // 5.5 h of jiffies; a bigger file is not one to plot
constexpr double kImpactForceN = 2.0;  // clearly above the load cell's noise (0.3 d = 3 mN) and ringing at rest

// A CSV read whole: a header of names, rows of cells, every row as wide as the header.
struct Table {
  std::string path;
  std::vector<std::string> names;
  std::vector<std::vector<std::string>> rows;

  long column(const std::string& name) const {
    const auto it = std::find(names.begin(), names.end(), name);
    return it == names.end() ? -1 : long(it - names.begin());
  }
  bool has(const std::string& name) const { return column(name) >= 0; }
  // The cell as a number; NaN if empty and `empty_ok`; throws naming the line otherwise.
  double number(std::size_t row, const std::string& name, bool empty_ok = false) const {
    const long c = column(name);
    if (c < 0) throw std::runtime_error(path + ": no column '" + name + "'");
    const std::string& cell = rows[row][std::size_t(c)];
    if (cell.empty() && empty_ok) return NAN;
    char* end = nullptr;
    const double v = std::strtod(cell.c_str(), &end);
    if (cell.empty() || *end != '\0' || !std::isfinite(v)) {
      throw std::runtime_error(path + ": line " + std::to_string(row + 2) + ": " + name + " is not a number");
    }
    return v;
  }
};

// std::getline, but never more than one byte past kMaxLineLength: a file without line ends (a
// sparse file, 200 MB of "1,") is refused at once instead of read into memory whole.
bool read_bounded_line(std::istream& in, std::string& line) {
  line.clear();
  for (int c; (c = in.get()) != std::char_traits<char>::eof();) {
    if (c == '\n') return true;
    line.push_back(char(c));
    if (line.size() > kMaxLineLength + 1) return true;  // long enough to be refused
  }
  return !line.empty();
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream stream(line);
  for (std::string cell; std::getline(stream, cell, ',');) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

Table read_table(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  Table t;
  t.path = path;
  std::string line;
  for (std::size_t number = 1; read_bounded_line(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.size() > kMaxLineLength) throw std::runtime_error(path + ": line " + std::to_string(number) + " is too long");
    for (unsigned char c : line) {
      if (c < 0x20 && c != '\t') throw std::runtime_error(path + ": line " + std::to_string(number) + " holds binary data");
    }
    if (line.empty()) continue;
    auto cells = split_csv(line);
    if (t.names.empty()) {
      t.names = std::move(cells);
      continue;
    }
    if (cells.size() != t.names.size()) {
      throw std::runtime_error(path + ": line " + std::to_string(number) + " has " + std::to_string(cells.size()) +
                               " fields, not " + std::to_string(t.names.size()));
    }
    if (t.rows.size() == kMaxRows) {
      throw std::runtime_error(path + ": more than " + std::to_string(kMaxRows) + " rows, more than a plot shows");
    }
    t.rows.push_back(std::move(cells));
  }
  if (t.names.empty()) throw std::runtime_error(path + ": empty");
  if (t.rows.empty()) throw std::runtime_error(path + ": no data rows");
  return t;
}

std::string terminal_for(const std::string& output) {
  const auto dot = output.rfind('.');
  const std::string ext = dot == std::string::npos ? "" : output.substr(dot + 1);
  if (ext == "png") return "pngcairo size 1200,700 font 'Sans,11'";
  if (ext == "svg") return "svg size 1200,700 dynamic font 'Sans,11'";
  throw std::runtime_error("output must end in .png or .svg: " + output);
}

std::string quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

std::string preamble(const std::string& output, const std::string& title) {
  std::ostringstream gp;
  gp << "set terminal " << terminal_for(output) << "\n"
     << "set output " << quoted(output) << "\n"
     << "set datafile separator ','\n"
     << "set datafile missing ''\n"
     << "set title " << quoted(title) << "\n"
     << "set grid\nset key top left box opaque\n";
  return gp.str();
}

// A labelled vertical line; `left`: the label on the line's left, so two close lines stay readable.
void vertical_line(std::ostream& gp, int tag, double x, const char* colour, const char* dash, const std::string& text,
                   bool left = false) {
  gp << "set arrow " << tag << " from " << x << ", graph 0 to " << x << ", graph 1 nohead dt " << dash << " lc rgb '"
     << colour << "'\n"
     << "set label " << tag << " " << quoted(text) << " at " << x << ", graph 0.97 "
     << (left ? "right offset -0.5,0" : "offset 0.5,0") << "\n";
}

// A label with an arrow pointing at (x, y) from a little up and to the right.
void pointer(std::ostream& gp, int tag, double x, double y, double dx_s, double dy_n, const std::string& text) {
  gp << "set arrow " << tag << " from " << x + dx_s << "," << y + dy_n << " to " << x << "," << y
     << " head size 0.1,20 lc rgb '#333333'\n"
     << "set label " << tag << " " << quoted(text) << " at " << x + dx_s << "," << y + dy_n
     << " offset 0.3,0.6 textcolor rgb '#333333'\n";
}

// ------------------------------------------------------------------------------------ cycle plot
struct CycleSummary {
  double open_s = -1.0;
  double impact_s = -1.0;   // first landing
  double cutoff_s = -1.0;
  double landed_s = -1.0;   // the rest-drop has landed
  double final_static_kg = 0.0;
  double force_max_n = 0.0;
  std::size_t rows = 0;
};

CycleSummary summarise_cycle(const Table& t) {
  CycleSummary s;
  int previous_valve = 0;
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    const double time = t.number(i, "t_s");
    const int valve = int(t.number(i, "valve"));
    const double force = t.number(i, "force_n", true);
    const double static_kg = t.number(i, "static_kg", true);
    const double in_flight = t.number(i, "in_flight_kg", true);
    t.number(i, "raw");
    t.number(i, "filtered_g", true);
    if (!std::isnan(static_kg)) s.final_static_kg = static_kg;
    if (!std::isnan(force)) s.force_max_n = std::max(s.force_max_n, force);
    if (valve != 0 && previous_valve == 0 && s.open_s < 0) s.open_s = time;
    if (valve == 0 && previous_valve != 0 && s.cutoff_s < 0) s.cutoff_s = time;
    if (s.open_s >= 0 && s.impact_s < 0 && (static_kg > 1e-4 || force > kImpactForceN)) s.impact_s = time;
    if (s.cutoff_s >= 0 && s.landed_s < 0 && !std::isnan(in_flight) && in_flight < 1e-6) s.landed_s = time;
    previous_valve = valve;
    ++s.rows;
  }
  return s;
}

// The force at the first row at or after `time_s`.
double force_at(const Table& t, double time_s) {
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    if (t.number(i, "t_s") >= time_s) {
      const double f = t.number(i, "force_n", true);
      return std::isnan(f) ? 0.0 : f;
    }
  }
  return 0.0;
}

std::string cycle_script(const Table& t, const std::string& output, const CycleSummary& s, double g,
                         const std::string& replay_csv) {
  std::ostringstream gp;
  gp << preamble(output, "Dosing cycle: force on the load cell") << "set key right center box opaque\n"
     << "set xlabel 'time (s)'\nset ylabel 'force above the empty container (N)'\n"
     << "set y2label 'valve command (0 closed, 1 half, 2 open)'\n"
     << "set y2range [-0.2:8]\nset y2tics 0,1,2\nset ytics nomirror\n";
  if (s.open_s >= 0) vertical_line(gp, 1, s.open_s, "#2ca02c", "3", "valve open");
  if (s.cutoff_s >= 0) vertical_line(gp, 2, s.cutoff_s, "#d62728", "2", "cutoff");
  // The phases of thesis fig. 2.3, each pointed at where it shows in this run.
  const double span_n = std::max(1.0, s.force_max_n);
  const double span_s = std::max(0.5, t.number(t.rows.size() - 1, "t_s") - t.number(0, "t_s"));
  if (s.impact_s >= 0) {
    pointer(gp, 10, s.impact_s, force_at(t, s.impact_s), 0.04 * span_s, 0.12 * span_n, "impulse step");
  }
  if (s.impact_s >= 0 && s.cutoff_s > s.impact_s) {
    const double mid = 0.5 * (s.impact_s + s.cutoff_s);
    pointer(gp, 11, mid, force_at(t, mid), -0.02 * span_s, 0.15 * span_n, "ramp");
  }
  if (s.cutoff_s >= 0) {
    const double end = s.landed_s > s.cutoff_s ? s.landed_s : s.cutoff_s + 0.4;
    const double mid = 0.5 * (s.cutoff_s + end);
    pointer(gp, 12, mid, force_at(t, mid), 0.05 * span_s, 0.12 * span_n, "rest-drop");
    const double ring = end + 0.15;
    pointer(gp, 13, ring, force_at(t, ring), 0.07 * span_s, -0.18 * span_n, "ringing");
  }
  const double final_n = s.final_static_kg * g;
  gp << "plot " << quoted(t.path) << " using 't_s':'force_n' with lines lw 1.5 lc rgb '#1f77b4' title 'force (N)', \\\n"
     << "  '' using 't_s':(column('filtered_g')*" << g
     << "/1000) with lines lw 1 lc rgb '#ff7f0e' title 'filtered weight x g (N)', \\\n"
     << "  '' using 't_s':(column('static_kg')*" << g
     << ") with lines dt 4 lc rgb '#7f7f7f' title 'static mass x g (N)', \\\n";
  if (!replay_csv.empty()) {
    gp << "  " << quoted(replay_csv) << " using 't_s':(column('prediction_g')*" << g
       << "/1000) with lines lw 1.5 lc rgb '#8c564b' title 'model: predicted final weight x g (N)', \\\n";
  }
  gp << "  " << final_n << " with lines dt 2 lc rgb '#9467bd' title sprintf('final static %.3f kg', "
     << s.final_static_kg << "), \\\n"
     << "  " << quoted(t.path) << " using 't_s':'valve' axes x1y2 with steps lw 1.5 lc rgb '#2ca02c' title 'valve'\n";
  return gp.str();
}

// ----------------------------------------------------------------------------------- replay plot
struct ReplaySummary {
  double dose_s = -1.0, cutoff_s = -1.0, recorded_cutoff_s = -1.0;
  std::size_t rows = 0;
};

ReplaySummary summarise_replay(const Table& t) {
  ReplaySummary s;
  int previous_valve = 0, previous_recorded = -1;
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    const double time = t.number(i, "t_s");
    const int valve = int(t.number(i, "valve"));
    const double recorded = t.has("recorded_valve") ? t.number(i, "recorded_valve", true) : NAN;
    t.number(i, "filtered_g");
    t.number(i, "prediction_g", true);
    if (t.has("state") && s.dose_s < 0 && t.number(i, "state") == 1) s.dose_s = time;
    if (valve == 0 && previous_valve != 0 && s.cutoff_s < 0) s.cutoff_s = time;
    if (!std::isnan(recorded)) {
      if (int(recorded) == 0 && previous_recorded > 0 && s.recorded_cutoff_s < 0) s.recorded_cutoff_s = time;
      previous_recorded = int(recorded);
    }
    previous_valve = valve;
    ++s.rows;
  }
  return s;
}

std::string replay_script(const Table& t, const std::string& output, const ReplaySummary& s, double target_g) {
  std::ostringstream gp;
  gp << preamble(output, "Replay: what the firmware decided") << "set key right center box opaque\n"
     << "set xlabel 'time (s)'\nset ylabel 'weight (g)'\n"
     << "set y2label 'valve (0 closed, 1 half, 2 open)'\n"
     << "set y2range [-0.2:8]\nset y2tics 0,1,2\nset ytics nomirror\n";
  if (s.cutoff_s >= 0) {
    vertical_line(gp, 1, s.cutoff_s, "#d62728", "2", "firmware cutoff",
                  s.recorded_cutoff_s > s.cutoff_s && s.recorded_cutoff_s != s.cutoff_s);
  }
  if (s.recorded_cutoff_s >= 0 && s.recorded_cutoff_s != s.cutoff_s) {
    vertical_line(gp, 2, s.recorded_cutoff_s, "#7f7f7f", "3", "recorded cutoff", s.recorded_cutoff_s < s.cutoff_s);
  }
  const std::string weight = t.has("gross_g") ? "gross_g" : "filtered_g";
  gp << "plot " << quoted(t.path) << " using 't_s':'" << weight
     << "' with lines lw 1 lc rgb '#1f77b4' title 'weight, unfiltered (g)', \\\n"
     << "  '' using 't_s':'filtered_g' with lines lw 1.5 lc rgb '#ff7f0e' title 'filtered weight (g)', \\\n"
     << "  '' using 't_s':'prediction_g' with lines lw 2 lc rgb '#8c564b' title 'model: predicted final weight (g)', \\\n";
  if (target_g > 0) gp << "  " << target_g << " with lines dt 2 lc rgb '#9467bd' title 'target " << target_g << " g', \\\n";
  if (t.has("recorded_valve")) {
    gp << "  '' using 't_s':'recorded_valve' axes x1y2 with steps lw 3 lc rgb '#bbbbbb' title 'valve as recorded', \\\n";
  }
  gp << "  " << quoted(t.path) << " using 't_s':'valve' axes x1y2 with steps lw 1.5 lc rgb '#2ca02c' title 'valve the firmware commanded'\n";
  return gp.str();
}

// ------------------------------------------------------------------------------------ bench plot
struct BenchPoint {
  double time_ratio, maxdev_g;
};

// The points no other point beats in both time and worst error, by increasing time.
std::vector<BenchPoint> pareto_front(std::vector<BenchPoint> points) {
  std::sort(points.begin(), points.end(), [](const BenchPoint& a, const BenchPoint& b) {
    return a.time_ratio < b.time_ratio || (a.time_ratio == b.time_ratio && a.maxdev_g < b.maxdev_g);
  });
  std::vector<BenchPoint> front;
  for (const BenchPoint& p : points) {
    if (front.empty() || p.maxdev_g < front.back().maxdev_g) front.push_back(p);
  }
  return front;
}

std::string bench_script(const Table& t, const std::string& output, std::map<std::string, std::vector<BenchPoint>>& by_strategy) {
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    const std::string& strategy = t.rows[i][std::size_t(t.column("strategy"))];
    by_strategy[strategy].push_back({t.number(i, "time_ratio"), t.number(i, "maxdev_g")});
  }
  static const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf"};
  std::ostringstream gp;
  gp << preamble(output, "Bench: Pareto fronts, dosing time against worst error")
     << "set datafile separator whitespace\n"
     << "set xlabel 'dosing time / ideal time (1)'\nset ylabel 'worst deviation from target (g)'\n"
     << "set key top right box opaque\nset logscale y\n";
  std::size_t n = 0;
  for (const auto& [strategy, points] : by_strategy) {
    gp << "$all" << n << " << EOD\n";
    for (const BenchPoint& p : points) gp << p.time_ratio << " " << p.maxdev_g << "\n";
    gp << "EOD\n$front" << n << " << EOD\n";
    for (const BenchPoint& p : pareto_front(points)) gp << p.time_ratio << " " << p.maxdev_g << "\n";
    gp << "EOD\n";
    ++n;
  }
  gp << "plot ";
  n = 0;
  for (const auto& [strategy, points] : by_strategy) {
    const char* colour = kColours[n % (sizeof kColours / sizeof *kColours)];
    if (n > 0) gp << ", \\\n  ";
    gp << "$all" << n << " using 1:2 with points pt 7 ps 0.6 lc rgb '" << colour << "' notitle, "
       << "$front" << n << " using 1:2 with linespoints lw 2 pt 7 ps 1.2 lc rgb '" << colour << "' title "
       << quoted(strategy + " (front)");
    ++n;
  }
  gp << "\n";
  return gp.str();
}

}  // namespace

int run_plot_command(int argc, char** argv) {
  std::string input, output, replay;
  double g = 9.81, target_g = 0;
  CLI::App app{"dynweigh plot: draw a CSV as PNG or SVG with gnuplot; the header decides what is drawn:\n"
               "  cycle CSV (dynweigh-fw --csv, dynweigh sim): force against time, valve, cutoff, phases labelled\n"
               "  replay CSV (dynweigh replay --csv): weight, filtered weight, the model's prediction, valve, cutoff\n"
               "  bench CSV (columns strategy,time_ratio,maxdev_g): one Pareto front per strategy"};
  app.add_option("csv", input, "the CSV")->required();
  app.add_option("-o,--output", output, "OUT.png or OUT.svg")->required();
  app.add_option("--replay", replay, "cycle plots: draw the prediction from this replay CSV of the same run");
  app.add_option("--target", target_g, "replay plots: draw the dose's target, grams")->check(FiniteRange(0.0, 1e9));
  app.add_option("--g", g, "gravity used to draw masses as forces, m/s^2")->capture_default_str()->check(FiniteRange(0.1, 100.0));
  if (const auto exit_status = tools::parse_command_line(app, argc, argv, "dynweigh plot")) return *exit_status;
  bool created = false;
  try {
    terminal_for(output);
    created = check_writable(output);
    const Table table = read_table(input);
    const auto has_all = [&table](std::initializer_list<const char*> names) {
      return std::all_of(names.begin(), names.end(), [&table](const char* n) { return table.has(n); });
    };
    if (has_all({"strategy", "time_ratio", "maxdev_g"})) {
      std::map<std::string, std::vector<BenchPoint>> by_strategy;
      run_gnuplot(bench_script(table, output, by_strategy), output);
      std::printf("plot=%s\nkind=bench\nrows=%zu\nstrategies=%zu\n", output.c_str(), table.rows.size(), by_strategy.size());
      return 0;
    }
    if (has_all({"t_s", "prediction_g", "filtered_g", "valve"})) {
      const ReplaySummary s = summarise_replay(table);
      run_gnuplot(replay_script(table, output, s, target_g), output);
      std::printf("plot=%s\nkind=replay\nrows=%zu\ncutoff_s=%.2f\nrecorded_cutoff_s=%.2f\n", output.c_str(), s.rows, s.cutoff_s,
                  s.recorded_cutoff_s);
      return 0;
    }
    if (has_all({"t_s", "static_kg", "in_flight_kg", "force_n", "raw", "filtered_g", "valve"})) {
      if (!replay.empty()) summarise_replay(read_table(replay));  // refuse a bad replay before drawing
      const CycleSummary s = summarise_cycle(table);
      run_gnuplot(cycle_script(table, output, s, g, replay), output);
      std::printf("plot=%s\nkind=cycle\nrows=%zu\ncutoff_s=%.2f\nfinal_static_kg=%.6f\n", output.c_str(), s.rows, s.cutoff_s,
                  s.final_static_kg);
      return 0;
    }
    throw std::runtime_error(input + ": not a cycle, replay or bench CSV (header: " + table.names.front() + ",...)");
  } catch (const std::exception& e) {
    if (created) std::remove(output.c_str());  // no empty picture left behind
    std::fprintf(stderr, "dynweigh plot: %s\n", e.what());
    return 1;
  }
}

}  // namespace dynweigh::tools
