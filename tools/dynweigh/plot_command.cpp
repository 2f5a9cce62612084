// dynweigh plot: a cycle CSV drawn like the thesis' fig. 2.3: the force on the load cell against
// time, the valve marker, the cutoff and the final static weight.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "dynweigh/hal/host/lockstep_session.hpp"

namespace dynweigh::tools {
namespace {

struct CycleSummary {
  double open_s = -1.0;
  double cutoff_s = -1.0;
  double final_static_kg = 0.0;
  std::size_t rows = 0;
};

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream stream(line);
  for (std::string cell; std::getline(stream, cell, ',');) cells.push_back(cell);
  return cells;
}

CycleSummary summarise(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::string line;
  if (!std::getline(in, line) || line != hal::host::kTraceHeader) {
    throw std::runtime_error(path + ": not a cycle CSV (expected header " + hal::host::kTraceHeader + ")");
  }
  CycleSummary summary;
  int previous_valve = 0;
  while (std::getline(in, line)) {
    const auto cells = split_csv(line);
    if (cells.size() != 8) throw std::runtime_error(path + ": line " + std::to_string(summary.rows + 2) + " has " +
                                                    std::to_string(cells.size()) + " fields, not 8");
    try {
      const double t = std::stod(cells[0]);
      const int valve = std::stoi(cells[7]);
      if (!cells[2].empty()) summary.final_static_kg = std::stod(cells[2]);
      if (valve != 0 && previous_valve == 0 && summary.open_s < 0) summary.open_s = t;
      if (valve == 0 && previous_valve != 0) summary.cutoff_s = t;
      previous_valve = valve;
    } catch (const std::logic_error&) {
      throw std::runtime_error(path + ": line " + std::to_string(summary.rows + 2) + " is not numeric");
    }
    ++summary.rows;
  }
  if (summary.rows == 0) throw std::runtime_error(path + ": no data rows");
  return summary;
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

std::string gnuplot_script(const std::string& csv, const std::string& output, const CycleSummary& s, double g) {
  std::ostringstream gp;
  gp << "set terminal " << terminal_for(output) << "\n"
     << "set output " << quoted(output) << "\n"
     << "set datafile separator ','\n"
     << "set title 'Dosing cycle: force on the load cell'\n"
     << "set xlabel 'time (s)'\nset ylabel 'force above the empty container (N)'\n"
     << "set y2label 'valve command (0 closed, 1 half, 2 open)'\n"
     << "set y2range [-0.2:8]\nset y2tics 0,1,2\nset ytics nomirror\nset grid\n"
     << "set key top left box opaque\n";
  if (s.open_s >= 0) {
    gp << "set arrow 1 from " << s.open_s << ", graph 0 to " << s.open_s << ", graph 1 nohead dt 3 lc rgb '#2ca02c'\n"
       << "set label 1 'valve open' at " << s.open_s << ", graph 0.97 offset 0.5,0\n";
  }
  if (s.cutoff_s >= 0) {
    gp << "set arrow 2 from " << s.cutoff_s << ", graph 0 to " << s.cutoff_s << ", graph 1 nohead dt 2 lc rgb '#d62728'\n"
       << "set label 2 'cutoff' at " << s.cutoff_s << ", graph 0.97 offset 0.5,0\n";
  }
  const double final_n = s.final_static_kg * g;
  gp << "plot " << quoted(csv) << " using 1:5 every ::1 with lines lw 1.5 lc rgb '#1f77b4' title 'force (N)', \\\n"
     << "  '' using 1:($7*" << g << "/1000) every ::1 with lines lw 1 lc rgb '#ff7f0e' title 'filtered weight x g (N)', \\\n"
     << "  '' using 1:($3*" << g << ") every ::1 with lines dt 4 lc rgb '#7f7f7f' title 'static mass x g (N)', \\\n"
     << "  " << final_n << " with lines dt 2 lc rgb '#9467bd' title sprintf('final static %.3f kg', "
     << s.final_static_kg << "), \\\n"
     << "  '' using 1:8 every ::1 axes x1y2 with steps lw 1.5 lc rgb '#2ca02c' title 'valve'\n";
  return gp.str();
}

}  // namespace

int run_plot_command(int argc, char** argv) {
  std::string input, output;
  double g = 9.81;
  CLI::App app{"dynweigh plot: draw a cycle CSV (dynweigh-fw --csv / dynweigh sim) as PNG or SVG with gnuplot"};
  app.add_option("csv", input, "cycle CSV")->required();
  app.add_option("-o,--output", output, "OUT.png or OUT.svg")->required();
  app.add_option("--g", g, "gravity used to draw masses as forces, m/s^2")->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "dynweigh plot: %s\n", e.what());
    return 2;
  }
  try {
    const CycleSummary summary = summarise(input);
    const std::string script = gnuplot_script(input, output, summary, g);
    std::FILE* gnuplot = popen("gnuplot", "w");
    if (!gnuplot) throw std::runtime_error("cannot start gnuplot (apt-get install gnuplot-nox)");
    std::fwrite(script.data(), 1, script.size(), gnuplot);
    const int status = pclose(gnuplot);
    if (status != 0) throw std::runtime_error("gnuplot failed drawing " + output);
    std::printf("plot=%s\nrows=%zu\ncutoff_s=%.2f\nfinal_static_kg=%.6f\n", output.c_str(), summary.rows,
                summary.cutoff_s, summary.final_static_kg);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dynweigh plot: %s\n", e.what());
    return 1;
  }
}

}  // namespace dynweigh::tools
