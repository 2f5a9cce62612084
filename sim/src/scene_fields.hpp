#pragma once
// One table of every numeric scene parameter: its JSON section and key, the key --describe prints,
// and the range a scene file may set. The loader and the description both walk it, so a new
// parameter is added in one place.
#include <limits>

#include "dynweigh/sim/scene.hpp"

namespace dynweigh::sim::detail {

struct FieldRange {
  double low;
  double high;
  bool low_open;  // true: low itself is not allowed
};

inline constexpr double kHuge = 1e12;
inline constexpr FieldRange kPositive{0.0, kHuge, true};
inline constexpr FieldRange kNonNegative{0.0, kHuge, false};
inline constexpr FieldRange kFraction{0.0, 1.0, false};
inline constexpr FieldRange kAnyFinite{-kHuge, kHuge, false};

// Calls visit(section, key, describe_key, value&, range) for every numeric field; section is ""
// for top-level fields. SceneT is Scene or const Scene.
template <typename SceneT, typename Visit>
void visit_scene_fields(SceneT& s, Visit&& visit) {
  visit("", "g", "g", s.g, FieldRange{0.0, 100.0, true});
  visit("", "internal_step_s", "internal_step_s", s.internal_step_s, FieldRange{1e-6, 0.010, false});

  visit("silo", "bore_m", "bore_m", s.silo.bore_m, FieldRange{0.0, 2.0, true});
  visit("silo", "bulk_density", "bulk_density", s.silo.bulk_density, FieldRange{0.0, 1e5, true});
  visit("silo", "beverloo_C", "beverloo_C", s.silo.beverloo_C, FieldRange{0.0, 10.0, true});
  visit("silo", "beverloo_k", "beverloo_k", s.silo.beverloo_k, FieldRange{0.0, 10.0, false});
  visit("silo", "grain_d_m", "grain_d_m", s.silo.grain_d_m, FieldRange{0.0, 0.1, false});
  visit("silo", "fill_kg", "silo_fill_kg", s.silo.fill_kg, kNonNegative);
  visit("silo", "alpha_start", "alpha_start", s.silo.alpha_start, FieldRange{0.0, 1.0, true});
  visit("silo", "alpha_settle_s", "alpha_settle_s", s.silo.alpha_settle_s, FieldRange{0.0, 1e3, false});
  visit("silo", "fluctuation_rms", "fluctuation_rms", s.silo.fluctuation_rms, FieldRange{0.0, 0.5, false});
  visit("silo", "fluctuation_correlation_s", "fluctuation_correlation_s", s.silo.fluctuation_correlation_s,
        FieldRange{0.0, 1e3, true});
  visit("silo", "flow_factor", "flow_factor", s.silo.flow_factor, FieldRange{0.0, 1.0, true});
  visit("silo", "refill_below_kg", "silo_refill_below_kg", s.silo.refill_below_kg, kNonNegative);
  visit("silo", "refill_rate_kg_s", "silo_refill_rate_kg_s", s.silo.refill_rate_kg_s, FieldRange{0.0, 1e3, true});

  visit("valve", "dead_time_s", "valve_dead_time_s", s.valve.dead_time_s, FieldRange{0.0, 10.0, false});
  visit("valve", "dead_time_jitter_s", "valve_dead_time_jitter_s", s.valve.dead_time_jitter_s,
        FieldRange{0.0, 1.0, false});
  visit("valve", "full_stroke_s", "valve_full_stroke_s", s.valve.full_stroke_s, FieldRange{0.0, 60.0, false});

  visit("gate", "discharge_kg_s", "gate_discharge_kg_s", s.gate.discharge_kg_s, FieldRange{0.0, 1e3, true});
  visit("gate", "stroke_s", "gate_stroke_s", s.gate.stroke_s, FieldRange{0.0, 60.0, false});

  visit("column", "fall_height_m", "fall_height_m", s.column.fall_height_m, FieldRange{0.0, 100.0, true});
  visit("column", "container_diameter_m", "container_diameter_m", s.column.container_diameter_m,
        FieldRange{0.0, 10.0, true});
  visit("column", "repose_angle_deg", "repose_angle_deg", s.column.repose_angle_deg, FieldRange{0.0, 89.0, true});

  visit("pile_top", "flat_radius_m", "pile_top_flat_radius_m", s.pile_top.flat_radius_m, FieldRange{0.0, 5.0, false});
  visit("pile_top", "dent_depth_m", "pile_top_dent_depth_m", s.pile_top.dent_depth_m, FieldRange{0.0, 10.0, false});
  visit("pile_top", "dent_settle_s", "pile_top_dent_settle_s", s.pile_top.dent_settle_s, FieldRange{0.0, 1e3, true});

  visit("impact", "relaxation_s", "impact_relaxation_s", s.impact.relaxation_s, FieldRange{0.0, 100.0, false});

  visit("avalanche", "critical_kg", "avalanche_critical_kg", s.avalanche.critical_kg, kPositive);
  visit("avalanche", "force_n", "avalanche_force_n", s.avalanche.force_n, kNonNegative);
  visit("avalanche", "duration_s", "avalanche_duration_s", s.avalanche.duration_s, FieldRange{0.0, 100.0, true});

  visit("platform", "container_kg", "container_kg", s.platform.container_kg, kPositive);
  visit("platform", "natural_hz", "platform_hz", s.platform.natural_hz, FieldRange{0.0, 1e4, true});
  visit("platform", "damping_ratio", "platform_zeta", s.platform.damping_ratio, FieldRange{0.0, 100.0, false});

  visit("load_cell", "capacity_kg", "capacity_kg", s.load_cell.capacity_kg, kPositive);
  visit("load_cell", "counts_per_kg", "counts_per_kg", s.load_cell.counts_per_kg, FieldRange{0.0, 1e9, true});
  visit("load_cell", "zero_counts", "zero_counts", s.load_cell.zero_counts, FieldRange{-1e9, 1e9, false});
  visit("load_cell", "noise_counts_rms", "noise_counts_rms", s.load_cell.noise_counts_rms, FieldRange{0.0, 1e6, false});
  visit("load_cell", "overload_fraction", "overload_fraction", s.load_cell.overload_fraction,
        FieldRange{1.0, 10.0, false});

  visit("creep", "fraction", "creep_fraction", s.creep.fraction, FieldRange{0.0, 0.1, false});
  visit("creep", "time_constant_s", "creep_time_constant_s", s.creep.time_constant_s, FieldRange{0.0, 1e9, true});

  visit("hourglass", "silo_tare_kg", "hourglass_silo_tare_kg", s.hourglass.silo_tare_kg, kNonNegative);
}

}  // namespace dynweigh::sim::detail
