#include "trace_csv.hpp"

#include <stdexcept>

namespace dynweigh::tools {

TraceCsv::TraceCsv(const std::string& path) : file_(std::fopen(path.c_str(), "w")) {
  if (!file_) throw std::runtime_error("cannot write " + path);
  std::fprintf(file_, "%s\n", hal::host::kTraceHeader);
}

TraceCsv::~TraceCsv() { std::fclose(file_); }

void TraceCsv::write(const hal::host::TraceRow& r) {
  if (!r.has_filtered) {
    std::fprintf(file_, "%.2f,%u,%.6f,%.6f,%.4f,%d,,%d\n", r.t_s, r.jiffy, r.static_kg, r.in_flight_kg, r.force_n,
                 r.raw, r.valve);
    return;
  }
  std::fprintf(file_, "%.2f,%u,%.6f,%.6f,%.4f,%d,%.1f,%d\n", r.t_s, r.jiffy, r.static_kg, r.in_flight_kg,
               r.force_n, r.raw, r.filtered_g, r.valve);
}

}  // namespace dynweigh::tools
