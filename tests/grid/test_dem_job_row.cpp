// A DEM job's result as a grid row: what another rank sends, or a journal holds, reads back to
// the very same doubles, so the calibration fitted from it is the same bytes as one fitted from
// results computed here.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "dem_job_row.hpp"

namespace granular = dynweigh::granular;
using dynweigh::tools::decode_dem_job_row;
using dynweigh::tools::dem_job_key;
using dynweigh::tools::encode_dem_job_row;

namespace {

// Values that a short format would round: thirds, tenths, the smallest normal and a subnormal,
// a near-zero rate of a jammed orifice, negative zero.
granular::DemJobResult awkward_result() {
  granular::DemJobResult r;
  r.run.time_s = {0.001, 0.002, 1.0 / 3.0};
  r.run.force_n = {-0.0, 2.0 / 3.0, 1e300};
  r.run.released_kg = {std::numeric_limits<double>::min(), std::numeric_limits<double>::denorm_min(), 0.1};
  r.run.outflow = {0.7 / 3.0, 1.1, 0.21212121212121213, 4711.0};
  r.run.grain_diameter_m = 0.06 / 7.0;
  r.run.disc_mass_kg = 1.0 / 7.0;
  r.run.slot_depth_m = std::acos(-1.0) * 0.06 / 4.0;
  r.run.bed_bulk_density = 1492.8234561;
  r.run.released_total_kg = 0.30000000000000004;
  r.run.lost_kg = -4.6858e-28;
  r.run.settle_s = 1.0 / 9.0;
  r.run.discs = 1200;
  r.run.steps = 9007199254740993LL - 1;  // 2^53: the largest count a double holds exactly
  r.run.particle_steps = 1.5e9;
  r.run.cpu_seconds = 0.856067123;
  r.steady_rate_kg_s = 1.9813099999999999;
  r.rate_per_depth_kg_s_m = 42.045 / 3.0;
  r.features = {true, 0.5233, 8.7279 / 3.0, 20.35, 0.003462, 5.00214};
  return r;
}

TEST(DemJobRow, ReadsBackToTheSameDoubles) {
  granular::DemJob job;
  job.seed = 7;
  const granular::DemJobResult r = awkward_result();
  const std::string row = encode_dem_job_row(r);
  EXPECT_EQ(row.find_first_of("\t\r\n"), std::string::npos) << "a row must fit one journal line";
  const granular::DemJobResult back = decode_dem_job_row(job, row);
  EXPECT_EQ(back.job.seed, 7u);
  const auto same_bits = [](double a, double b) { return a == b && std::signbit(a) == std::signbit(b); };
  for (std::size_t k = 0; k < r.run.time_s.size(); ++k) {
    EXPECT_TRUE(same_bits(back.run.time_s[k], r.run.time_s[k])) << k;
    EXPECT_TRUE(same_bits(back.run.force_n[k], r.run.force_n[k])) << k;
    EXPECT_TRUE(same_bits(back.run.released_kg[k], r.run.released_kg[k])) << k;
  }
  EXPECT_EQ(back.run.time_s.size(), r.run.time_s.size());
  EXPECT_EQ(back.run.outflow.alpha, r.run.outflow.alpha);
  EXPECT_EQ(back.run.outflow.sampled_discs, r.run.outflow.sampled_discs);
  EXPECT_EQ(back.run.slot_depth_m, r.run.slot_depth_m);
  EXPECT_EQ(back.run.lost_kg, r.run.lost_kg);
  EXPECT_EQ(back.run.steps, r.run.steps);
  EXPECT_EQ(back.run.cpu_seconds, r.run.cpu_seconds);
  EXPECT_EQ(back.rate_per_depth_kg_s_m, r.rate_per_depth_kg_s_m);
  EXPECT_TRUE(back.features.valid);
  EXPECT_EQ(back.features.impulse_n, r.features.impulse_n);
  EXPECT_EQ(encode_dem_job_row(back), row) << "encoding is a fixed point";
}

TEST(DemJobRow, RefusesARowCutShortOrWithAStrayField) {
  const std::string row = encode_dem_job_row(awkward_result());
  const granular::DemJob job;
  EXPECT_THROW(decode_dem_job_row(job, row.substr(0, row.size() / 2)), std::runtime_error);
  EXPECT_THROW(decode_dem_job_row(job, row.substr(0, row.find(',', 20))), std::runtime_error);
  EXPECT_THROW(decode_dem_job_row(job, row + " extra=1"), std::runtime_error);
  EXPECT_THROW(decode_dem_job_row(job, ""), std::runtime_error);
}

TEST(DemJobRow, KeysNameKindSeedAndWidth) {
  granular::DemJob dose;
  dose.seed = 3;
  granular::DemJob sweep;
  sweep.kind = granular::DemJobKind::discharge;
  sweep.seed = 1003;
  sweep.config.discs_across_orifice = 6.5;
  EXPECT_EQ(dem_job_key(dose), "dose seed=3");
  EXPECT_EQ(dem_job_key(sweep), "discharge orifice_discs=6.5 seed=1003");
}

}  // namespace
