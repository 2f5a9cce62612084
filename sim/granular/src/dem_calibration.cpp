#include "dynweigh/granular/dem_calibration.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "dynweigh/granular/silo2d.hpp"

namespace dynweigh::granular {

namespace {

// Start of the steady part of an opening: the gate fully open and 0.1 s of flow.
double steady_start_s(const DemSceneConfig& c) { return c.valve_dead_time_s + c.valve_full_stroke_s + 0.1; }

double run_duration_s(const DemSceneRun& run) { return run.time_s.empty() ? 0.0 : run.time_s.back(); }

MeanAndError mean_and_error(const std::vector<double>& values) {
  MeanAndError m;
  if (values.empty()) return m;
  for (const double v : values) m.mean += v;
  const double n = static_cast<double>(values.size());
  m.mean /= n;
  if (values.size() > 1) {
    double squares = 0;
    for (const double v : values) squares += (v - m.mean) * (v - m.mean);
    m.standard_error = std::sqrt(squares / (n - 1) / n);
  }
  return m;
}

std::vector<const DemJobResult*> doses_of(const std::vector<DemJobResult>& results) {
  std::vector<const DemJobResult*> doses;
  for (const DemJobResult& r : results) {
    if (r.job.kind == DemJobKind::scene_dose) doses.push_back(&r);
  }
  return doses;
}

// The lumped scene used for fitting: no random disturbance, so a fit sees the parameters only.
sim::Scene deterministic(sim::Scene scene) {
  scene.silo.fluctuation_rms = 0;
  scene.valve.dead_time_jitter_s = 0;
  return rigid_scale_scene(scene);
}

double released_rms_kg(const sim::Scene& scene, const LumpedDose& dem, double close_s, double until_s) {
  const LumpedDose lumped = run_lumped_dose(scene, close_s, until_s, dem.time_s[1] - dem.time_s[0], 1);
  double sum = 0, count = 0;
  for (std::size_t k = 0; k < lumped.time_s.size() && k < dem.time_s.size(); ++k) {
    const double e = lumped.released_kg[k] - dem.released_kg[k];
    sum += e * e;
    count += 1;
  }
  return count > 0 ? std::sqrt(sum / count) : 0.0;
}

// alpha_start and alpha_settle_s: a grid, then a finer grid around its best point.
void fit_start_up(sim::Scene& scene, const LumpedDose& dem, double close_s, double until_s, double& rms) {
  double best_a = scene.silo.alpha_start, best_tau = scene.silo.alpha_settle_s;
  rms = 1e300;
  double a_low = 0.02, a_high = 1.0, log_tau_low = std::log(0.002), log_tau_high = std::log(0.5);
  for (int round = 0; round < 3; ++round) {
    constexpr int kGrid = 16;
    for (int i = 0; i <= kGrid; ++i) {
      for (int j = 0; j <= kGrid; ++j) {
        sim::Scene trial = scene;
        trial.silo.alpha_start = std::clamp(a_low + (a_high - a_low) * i / kGrid, 0.01, 1.0);
        trial.silo.alpha_settle_s = std::exp(log_tau_low + (log_tau_high - log_tau_low) * j / kGrid);
        const double e = released_rms_kg(trial, dem, close_s, until_s);
        if (e < rms) {
          rms = e;
          best_a = trial.silo.alpha_start;
          best_tau = trial.silo.alpha_settle_s;
        }
      }
    }
    const double a_span = (a_high - a_low) / 8, log_span = (log_tau_high - log_tau_low) / 8;
    a_low = std::max(0.01, best_a - a_span);
    a_high = std::min(1.0, best_a + a_span);
    log_tau_low = std::log(best_tau) - log_span;
    log_tau_high = std::log(best_tau) + log_span;
  }
  scene.silo.alpha_start = best_a;
  scene.silo.alpha_settle_s = best_tau;
}

// The lumped relaxation_s whose signal gives the same relaxation estimate as `target_s`.
double matching_relaxation_s(sim::Scene scene, const DemSceneConfig& c, double duration_s, double period_s,
                             double target_s) {
  const auto estimate = [&](double relaxation) {
    scene.impact.relaxation_s = relaxation;
    const LumpedDose d = run_lumped_dose(scene, c.close_s, duration_s, period_s, 1);
    return force_signal_features(d.time_s, d.force_n, steady_landing_end_s(c)).relaxation_s;
  };
  double low = 0.0, high = 0.25;
  if (target_s <= estimate(low)) return 0.0;
  if (target_s >= estimate(high)) return high;
  for (int i = 0; i < 30; ++i) {
    const double mid = 0.5 * (low + high);
    (estimate(mid) < target_s ? low : high) = mid;
  }
  return 0.5 * (low + high);
}

// Mean of each 10 ms bin of a signal (jiffy means).
std::vector<double> jiffy_means(const std::vector<double>& time_s, const std::vector<double>& value, double until_s) {
  constexpr double kJiffyS = 0.010;
  const auto bins = static_cast<std::size_t>(until_s / kJiffyS);
  std::vector<double> sum(bins, 0.0), count(bins, 0.0);
  for (std::size_t k = 0; k < time_s.size(); ++k) {
    const auto bin = static_cast<std::size_t>(std::max(0.0, time_s[k] - 1e-9) / kJiffyS);
    if (bin < bins) {
      sum[bin] += value[k];
      count[bin] += 1;
    }
  }
  for (std::size_t b = 0; b < bins; ++b) sum[b] = count[b] > 0 ? sum[b] / count[b] : 0.0;
  return sum;
}

ModelComparison compare_signal(const std::string& model, double cpu, const LumpedDose& signal, const LumpedDose& dem,
                               const ForceSignalFeatures& reference, double steady_end_s) {
  ModelComparison m;
  m.model = model;
  m.cpu_seconds_per_run = cpu;
  m.features = force_signal_features(signal.time_s, signal.force_n, steady_end_s);
  m.dead_time_error_s = std::fabs(m.features.dead_time_s - reference.dead_time_s);
  m.impulse_error = relative_deviation(m.features.impulse_n, reference.impulse_n);
  m.slope_error = relative_deviation(m.features.slope_n_s, reference.slope_n_s);
  m.final_error = relative_deviation(m.features.final_n, reference.final_n);
  const double until = std::min(signal.time_s.back(), dem.time_s.back());
  const std::vector<double> a = jiffy_means(signal.time_s, signal.force_n, until);
  const std::vector<double> b = jiffy_means(dem.time_s, dem.force_n, until);
  double sum = 0;
  for (std::size_t k = 0; k < a.size(); ++k) sum += (a[k] - b[k]) * (a[k] - b[k]);
  m.signal_rms_error_n = a.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(a.size()));
  return m;
}

}  // namespace

std::vector<DemJob> dem_calibration_jobs(const sim::Scene& scene, const DemCalibrationOptions& o) {
  std::vector<DemJob> jobs;
  const DemSceneConfig dose = [&] {
    DemSceneConfig c = dem_scene_config(scene, o.close_s, o.discs_across_orifice);
    c.fill_discs = o.fill_discs;
    return c;
  }();
  for (const std::uint64_t seed : o.seeds) jobs.push_back(DemJob{DemJobKind::scene_dose, dose, seed});
  const double d = dose.bore_m / dose.discs_across_orifice;
  for (std::size_t k = 0; k < o.sweep_orifices.size(); ++k) {
    DemSceneConfig c = dose;
    c.with_container = false;
    c.close_s = o.sweep_close_s;
    c.bore_m = o.sweep_orifices[k] * d;  // same discs, same silo width in metres
    c.discs_across_orifice = o.sweep_orifices[k];
    c.silo_width_bores = dose.silo_width_bores * dose.bore_m / c.bore_m;
    jobs.push_back(DemJob{DemJobKind::discharge, c, o.seeds.empty() ? 1 : o.seeds.front() + 1000 + k});
  }
  return jobs;
}

DemJobResult run_dem_job(const DemJob& job, const std::function<void(double)>& progress) {
  DemJobResult r;
  r.job = job;
  r.run = run_dem_scene(job.config, job.seed, progress);
  const double steady_end = job.kind == DemJobKind::scene_dose ? job.config.close_s + job.config.valve_dead_time_s
                                                                : job.config.close_s;
  r.steady_rate_kg_s = steady_discharge_kg_s(r.run, steady_start_s(job.config), steady_end);
  r.rate_per_depth_kg_s_m = r.steady_rate_kg_s / r.run.slot_depth_m;
  if (job.kind == DemJobKind::scene_dose) {
    r.features = force_signal_features(r.run.time_s, r.run.force_n, steady_landing_end_s(job.config));
  }
  return r;
}

std::vector<DemJobResult> run_dem_jobs(const std::vector<DemJob>& jobs, int threads,
                                       const std::function<void(double)>& progress) {
  std::vector<DemJobResult> results(jobs.size());
  std::vector<double> done(jobs.size(), 0.0);
  std::mutex report;
  std::atomic<std::size_t> next{0};
  const auto worker = [&] {
    for (std::size_t k = next++; k < jobs.size(); k = next++) {
      std::function<void(double)> job_progress;
      if (progress) {
        job_progress = [&, k](double fraction) {
          const std::lock_guard<std::mutex> lock(report);
          done[k] = fraction;
          double sum = 0;
          for (const double f : done) sum += f;
          progress(sum / static_cast<double>(done.size()));
        };
      }
      results[k] = run_dem_job(jobs[k], job_progress);
    }
  };
  const int count = std::max(1, std::min<int>(threads, static_cast<int>(jobs.size())));
  std::vector<std::thread> pool;
  for (int t = 1; t < count; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  return results;
}

LumpedDose mean_dem_signal(const std::vector<DemJobResult>& results) {
  LumpedDose mean;
  const std::vector<const DemJobResult*> doses = doses_of(results);
  if (doses.empty()) return mean;
  std::size_t n = doses.front()->run.time_s.size();
  for (const DemJobResult* r : doses) n = std::min(n, r->run.time_s.size());
  mean.time_s.assign(doses.front()->run.time_s.begin(), doses.front()->run.time_s.begin() + static_cast<std::ptrdiff_t>(n));
  mean.force_n.assign(n, 0.0);
  mean.released_kg.assign(n, 0.0);
  for (const DemJobResult* r : doses) {
    for (std::size_t k = 0; k < n; ++k) {
      mean.force_n[k] += r->run.force_n[k] / static_cast<double>(doses.size());
      mean.released_kg[k] += r->run.released_kg[k] / static_cast<double>(doses.size());
    }
    mean.cpu_seconds += r->run.cpu_seconds;
  }
  return mean;
}

DemCalibration calibrate_from_dem(const sim::Scene& base, const std::vector<DemJobResult>& results,
                                  const DemCalibrationOptions& options) {
  const std::vector<const DemJobResult*> doses = doses_of(results);
  if (doses.empty()) throw std::invalid_argument("calibration from DEM needs at least one scene dose");
  DemCalibration cal;
  cal.scene = base;
  sim::Scene& scene = cal.scene;
  const DemSceneConfig& config = doses.front()->job.config;
  cal.grain_diameter_m = doses.front()->run.grain_diameter_m;
  cal.doses = doses.size();

  std::vector<double> rates, alphas, estimates, dead, impulse, slope, final, cpu, bulk;
  for (const DemJobResult* r : doses) {
    rates.push_back(r->steady_rate_kg_s);
    alphas.push_back(r->run.outflow.alpha);
    estimates.push_back(r->features.relaxation_s);
    dead.push_back(r->features.dead_time_s);
    impulse.push_back(r->features.impulse_n);
    slope.push_back(r->features.slope_n_s);
    final.push_back(r->features.final_n);
    cpu.push_back(r->run.cpu_seconds);
    bulk.push_back(r->run.bed_bulk_density);
  }
  cal.dem_rate_kg_s = mean_and_error(rates).mean;
  cal.flow_factor = mean_and_error(alphas);
  cal.dem_relaxation_estimate_s = mean_and_error(estimates);
  cal.dead_time_s = mean_and_error(dead);
  cal.impulse_n = mean_and_error(impulse);
  cal.slope_n_s = mean_and_error(slope);
  cal.final_n = mean_and_error(final);
  cal.dem_cpu_seconds_per_dose = mean_and_error(cpu).mean;
  cal.bed_bulk_density = mean_and_error(bulk).mean;

  // Beverloo: k from the 2D fit over the widths (the doses' own width included), C at the bore.
  const double d = cal.grain_diameter_m;
  cal.sweep_orifice_m.push_back(config.bore_m);
  cal.sweep_rate_per_depth.push_back(cal.dem_rate_kg_s / doses.front()->run.slot_depth_m);
  for (const DemJobResult& r : results) {
    if (r.job.kind != DemJobKind::discharge) continue;
    cal.sweep_orifice_m.push_back(r.job.config.bore_m);
    cal.sweep_rate_per_depth.push_back(r.rate_per_depth_kg_s_m);
  }
  cal.beverloo_k = scene.silo.beverloo_k;
  if (cal.sweep_orifice_m.size() >= 3) {
    const BeverlooFit fit = fit_beverloo_2d(cal.sweep_orifice_m, cal.sweep_rate_per_depth, d);
    cal.beverloo_k = fit.k;
    cal.beverloo_c_2d = fit.c / (scene.silo.bulk_density * std::sqrt(scene.g));
    cal.beverloo_worst_residual = fit.worst_relative_residual;
  }
  const double free_width = config.bore_m - cal.beverloo_k * d;
  if (!(free_width > 0)) throw std::runtime_error("calibration: the fitted Beverloo k closes the bore");
  cal.beverloo_c = cal.dem_rate_kg_s / (scene.silo.bulk_density * std::sqrt(scene.g) * std::pow(free_width, 2.5));
  scene.silo.beverloo_k = cal.beverloo_k;
  scene.silo.beverloo_C = cal.beverloo_c;
  scene.silo.grain_d_m = d;
  scene.silo.flow_factor = std::clamp(cal.flow_factor.mean, 1e-3, 1.0);

  // Start-up settling, from the released mass over the opening.
  const LumpedDose dem = mean_dem_signal(results);
  const double duration = run_duration_s(doses.front()->run);
  const double period = dem.time_s.size() > 1 ? dem.time_s[1] - dem.time_s[0] : config.sample_period_s;
  fit_start_up(scene, dem, config.close_s, config.close_s + config.valve_dead_time_s, cal.released_fit_rms_kg);
  cal.alpha_start = scene.silo.alpha_start;
  cal.alpha_settle_s = scene.silo.alpha_settle_s;

  // Impact relaxation by indirect inference, seed by seed for its uncertainty.
  std::vector<double> relaxations;
  for (const double estimate : estimates) {
    relaxations.push_back(matching_relaxation_s(deterministic(scene), config, duration, period, estimate));
  }
  cal.relaxation_s = mean_and_error(relaxations);
  scene.impact.relaxation_s =
      matching_relaxation_s(deterministic(scene), config, duration, period, cal.dem_relaxation_estimate_s.mean);
  (void)options;
  return cal;
}

std::vector<ModelComparison> compare_with_dem(const sim::Scene& base, const DemCalibration& calibration,
                                              const std::vector<DemJobResult>& results,
                                              const DemCalibrationOptions& options, int lumped_seeds) {
  std::vector<ModelComparison> rows;
  const std::vector<const DemJobResult*> doses = doses_of(results);
  if (doses.empty()) return rows;
  const DemSceneConfig& config = doses.front()->job.config;
  const double steady_end = steady_landing_end_s(config);
  const LumpedDose dem = mean_dem_signal(results);
  const ForceSignalFeatures reference = force_signal_features(dem.time_s, dem.force_n, steady_end);
  const double duration = dem.time_s.back();
  const double period = dem.time_s[1] - dem.time_s[0];
  const double per_dose = calibration.dem_cpu_seconds_per_dose;

  LumpedDose single;
  single.time_s = doses.front()->run.time_s;
  single.force_n = doses.front()->run.force_n;
  rows.push_back(compare_signal("dem_1_seed", per_dose, single, dem, reference, steady_end));
  char name[64];
  std::snprintf(name, sizeof name, "dem_mean_%zu_seeds", doses.size());
  rows.push_back(compare_signal(name, per_dose * static_cast<double>(doses.size()), dem, dem, reference, steady_end));

  const auto lumped_mean = [&](const sim::Scene& scene, const std::string& label) {
    LumpedDose mean;
    double cpu = 0;
    for (int s = 1; s <= lumped_seeds; ++s) {
      const LumpedDose d = run_lumped_dose(rigid_scale_scene(scene), options.close_s, duration, period,
                                           static_cast<std::uint64_t>(s));
      if (mean.time_s.empty()) {
        mean = d;
        for (double& f : mean.force_n) f = 0;
      }
      for (std::size_t k = 0; k < d.force_n.size(); ++k) mean.force_n[k] += d.force_n[k] / lumped_seeds;
      cpu += d.cpu_seconds;
    }
    rows.push_back(compare_signal(label, cpu / lumped_seeds, mean, dem, reference, steady_end));
  };
  lumped_mean(calibration.scene, "lumped_calibrated");
  lumped_mean(base, "lumped_uncalibrated");
  return rows;
}

std::string dem_calibration_notes(const DemCalibration& c, const DemCalibrationOptions& o) {
  char text[1600];
  std::snprintf(text, sizeof text,
                "{\"from\": \"dem\", \"command\": \"dynweigh calibrate --from dem\", "
                "\"dem\": \"2D slot of the bore's width and area, %.3g discs across it (d = %.4g m), %d discs, "
                "%zu seeds, open command at 0, close at %.3g s\", "
                "\"dem_rate_kg_s\": %.5g, \"beverloo_k_2d_fit\": %.4g, \"beverloo_worst_residual\": %.3g, "
                "\"flow_factor_standard_error\": %.3g, \"released_fit_rms_kg\": %.3g, "
                "\"dem_relaxation_estimate_s\": %.4g, \"relaxation_standard_error_s\": %.3g, "
                "\"dem_dead_time_s\": %.4g, \"dem_impulse_n\": %.4g, \"dem_slope_n_s\": %.4g, \"dem_final_n\": %.4g, "
                "\"dem_bed_bulk_density\": %.5g}",
                o.discs_across_orifice, c.grain_diameter_m, o.fill_discs, c.doses, o.close_s, c.dem_rate_kg_s,
                c.beverloo_k, c.beverloo_worst_residual, c.flow_factor.standard_error, c.released_fit_rms_kg,
                c.dem_relaxation_estimate_s.mean, c.relaxation_s.standard_error, c.dead_time_s.mean, c.impulse_n.mean,
                c.slope_n_s.mean, c.final_n.mean, c.bed_bulk_density);
  return text;
}

}  // namespace dynweigh::granular
