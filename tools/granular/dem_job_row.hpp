#pragma once
// A DEM job of the calibration as a job of the scenario grid (tools/grid): its key (what it runs,
// unique in the job list) and its result as one line of text that reads back to the very same
// doubles (%.17g), so a result computed by another rank, or read from a journal, fits the same
// scene as one computed here.
#include <string>

#include "dynweigh/granular/dem_calibration.hpp"

namespace dynweigh::tools {

// "dose seed=1", "discharge orifice_discs=6.5 seed=1002"
std::string dem_job_key(const granular::DemJob& job);

std::string encode_dem_job_row(const granular::DemJobResult& result);
// The result of `job` from its row; throws on a row that does not hold every field.
granular::DemJobResult decode_dem_job_row(const granular::DemJob& job, const std::string& row);

}  // namespace dynweigh::tools
