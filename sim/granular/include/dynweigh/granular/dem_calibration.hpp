#pragma once
// Calibration of a lumped scene from the 2D DEM of the same scene: the DEM
// runs are a list of independent jobs, each a pure function of (job, seed) returning one result
// row, so they can run on threads here or be handed to another back-end; the fit then turns the
// rows into the scene's lumped parameters:
// - Beverloo k from discharge runs over several orifice widths (2D fit, the rate per metre of
//   slot depth), and C so that the lumped 3D law gives the DEM's rate at the scene's bore with
//   the DEM's grain diameter;
// - the flow factor alpha (mean / peak speed across the slot, outflow_profile.hpp);
// - the start-up settling alpha_start, alpha_settle_s: the lumped released mass fitted to the
//   DEM's over the opening (least squares on a grid, then refined);
// - the impact relaxation time by indirect inference: the relaxation estimate of the DEM's
//   force signal is matched by the same estimate of the lumped signal (bisection on the lumped
//   relaxation_s), so what the estimator mixes in (stroke, start-up, the spread of fall times
//   across the profile) is mixed in alike on both sides; the seeds give its uncertainty.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "dynweigh/granular/dem_scene.hpp"
#include "dynweigh/granular/force_signal_features.hpp"
#include "dynweigh/sim/scene.hpp"

namespace dynweigh::granular {

// The DEM of a lumped scene (dem_scene.hpp says what is scaled).
DemSceneConfig dem_scene_config(const sim::Scene& scene, double close_s, double discs_across_orifice);

// The last time the stream lands as with the gate open: close command, valve dead time, and
// the shortest fall (with a generous outflow speed).
double steady_landing_end_s(const DemSceneConfig& config);

// A lumped dose of a scene with the DEM's schedule (open at 0, close at close_s), the support
// force and released mass sampled every `sample_period_s` until `duration_s`.
struct LumpedDose {
  std::vector<double> time_s, force_n, released_kg;
  double cpu_seconds = 0;
};
LumpedDose run_lumped_dose(const sim::Scene& scene, double close_s, double duration_s, double sample_period_s,
                           std::uint64_t seed);
// The scene as the DEM sees the scale: a rigid platform (the DEM's container floor is rigid).
sim::Scene rigid_scale_scene(sim::Scene scene);

enum class DemJobKind { scene_dose, discharge };

struct DemJob {
  DemJobKind kind = DemJobKind::scene_dose;
  DemSceneConfig config;
  std::uint64_t seed = 1;
};

struct DemJobResult {
  DemJob job;
  DemSceneRun run;
  double steady_rate_kg_s = 0;        // over the steady part of the opening
  double rate_per_depth_kg_s_m = 0;   // the same per metre of slot depth (2D)
  ForceSignalFeatures features;       // scene doses only
};

struct DemCalibrationOptions {
  double close_s = 0.8;
  double discs_across_orifice = 8.0;
  int fill_discs = 1200;
  std::vector<std::uint64_t> seeds{1, 2, 3};
  // Orifice widths in disc diameters of the Beverloo sweep (empty: keep the scene's k, fit C).
  std::vector<double> sweep_orifices{5.0, 6.5, 8.0, 10.0, 12.0};
  double sweep_close_s = 0.35;
};

std::vector<DemJob> dem_calibration_jobs(const sim::Scene& scene, const DemCalibrationOptions& options);
// One job: a pure function of the job (its seed included).
DemJobResult run_dem_job(const DemJob& job, const std::function<void(double)>& progress = {});
// All jobs on `threads` threads; results in the order of the jobs. `progress` gets the mean
// fraction done (called from the worker threads, serialised).
std::vector<DemJobResult> run_dem_jobs(const std::vector<DemJob>& jobs, int threads,
                                       const std::function<void(double)>& progress = {});

struct MeanAndError {
  double mean = 0;
  double standard_error = 0;  // of the mean over the seeds (0 with one seed)
};

struct DemCalibration {
  sim::Scene scene;               // the calibrated scene
  double grain_diameter_m = 0;    // of the DEM discs
  double dem_rate_kg_s = 0;       // at the scene's bore, mean over the seeds
  double beverloo_k = 0, beverloo_c = 0, beverloo_c_2d = 0, beverloo_worst_residual = 0;
  std::vector<double> sweep_orifice_m, sweep_rate_per_depth;  // the sweep's rows
  MeanAndError flow_factor;
  double alpha_start = 0, alpha_settle_s = 0, released_fit_rms_kg = 0;
  MeanAndError dem_relaxation_estimate_s;  // the estimator on the DEM signal
  MeanAndError relaxation_s;               // the lumped relaxation that reproduces it
  MeanAndError dead_time_s, impulse_n, slope_n_s, final_n;  // DEM features
  double bed_bulk_density = 0;
  double dem_cpu_seconds_per_dose = 0;
  std::size_t doses = 0;
};

// Fits the lumped parameters from the job results (doses and sweep) into a copy of `base`.
DemCalibration calibrate_from_dem(const sim::Scene& base, const std::vector<DemJobResult>& results,
                                  const DemCalibrationOptions& options);

// The mean over the seeds of the DEM doses' force signals (same sampling on every seed).
LumpedDose mean_dem_signal(const std::vector<DemJobResult>& results);

// Lumped against DEM: features of each model's signal and their deviation from the DEM's
// seed-mean features, with the CPU time of one run.
struct ModelComparison {
  std::string model;
  double cpu_seconds_per_run = 0;
  ForceSignalFeatures features;
  double dead_time_error_s = 0;      // absolute
  double impulse_error = 0, slope_error = 0, final_error = 0;  // relative
  double signal_rms_error_n = 0;     // rms of the difference of the sampled signals (DEM mean)
};
std::vector<ModelComparison> compare_with_dem(const sim::Scene& base, const DemCalibration& calibration,
                                              const std::vector<DemJobResult>& results,
                                              const DemCalibrationOptions& options, int lumped_seeds = 8);

// The calibration's figures as a JSON object (the scene file's "_calibration" note).
std::string dem_calibration_notes(const DemCalibration& calibration, const DemCalibrationOptions& options);

}  // namespace dynweigh::granular
