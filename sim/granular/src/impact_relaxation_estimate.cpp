#include "dynweigh/granular/impact_relaxation_estimate.hpp"

#include <cstddef>

namespace dynweigh::granular {

namespace {
// Least-squares line v = a + b t over samples [first, n).
void fit_line(const std::vector<double>& t, const std::vector<double>& v, std::size_t first, double& a, double& b) {
  const std::size_t n = t.size();
  double mt = 0, mv = 0;
  for (std::size_t k = first; k < n; ++k) {
    mt += t[k];
    mv += v[k];
  }
  const double count = static_cast<double>(n - first);
  mt /= count;
  mv /= count;
  double stv = 0, stt = 0;
  for (std::size_t k = first; k < n; ++k) {
    stv += (t[k] - mt) * (v[k] - mv);
    stt += (t[k] - mt) * (t[k] - mt);
  }
  b = stt > 0 ? stv / stt : 0.0;
  a = mv - b * mt;
}
}  // namespace

ImpactRelaxationEstimate estimate_impact_relaxation(const std::vector<double>& time, const std::vector<double>& load,
                                                    double threshold, double late_fraction) {
  ImpactRelaxationEstimate e;
  const std::size_t n = time.size();
  if (n != load.size() || n < 16 || !(late_fraction > 0 && late_fraction < 1)) return e;
  // The late load level: mean of the second half of the record.
  double level = 0;
  for (std::size_t k = n / 2; k < n; ++k) level += load[k];
  level /= static_cast<double>(n - n / 2);
  if (!(level > 0)) return e;
  // The first sample at `threshold` of that level, then back to the start of the rise (the
  // container carries nothing before the first disc lands); t0 is put half a sample earlier.
  std::size_t landing = 0;
  while (landing < n && load[landing] < threshold * level) ++landing;
  if (landing + 16 > n) return e;
  while (landing > 0 && load[landing - 1] > 0) --landing;
  const double t0 = landing > 0 ? 0.5 * (time[landing - 1] + time[landing]) : time[0];
  const std::size_t late = landing + static_cast<std::size_t>((1.0 - late_fraction) * static_cast<double>(n - landing));
  double a, b;
  fit_line(time, load, late, a, b);
  e.landing_time = t0;
  e.load_slope = b;
  e.step_force = a + b * t0;
  if (!(e.step_force > 0)) return e;
  // Area between the asymptote and the load from t0 on (trapezoids; load(t0) = 0).
  double area = 0.5 * ((a + b * t0) + (a + b * time[landing] - load[landing])) * (time[landing] - t0);
  for (std::size_t k = landing + 1; k < n; ++k) {
    const double gap0 = a + b * time[k - 1] - load[k - 1];
    const double gap1 = a + b * time[k] - load[k];
    area += 0.5 * (gap0 + gap1) * (time[k] - time[k - 1]);
  }
  e.relaxation_time = area / e.step_force;
  e.valid = e.relaxation_time > 0;
  return e;
}

}  // namespace dynweigh::granular
