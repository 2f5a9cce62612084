#pragma once
// `dynweigh bench --plants random:N[@SEED] --ceiling`: for each plant and target of the family, the
// chance that a controller knowing the plant exactly lands a fill within X(1) (fill_ceiling.hpp), and
// the family's expected shares: what no strategy can be expected to beat (docs/plant-family.md).
#include "parallel_session.hpp"
#include "plant_family_bench.hpp"

namespace dynweigh::tools {

// One line per plant x target it holds (`ceiling plant= target_g= first= steady=`), then
// `summary ceiling plants= seed= fills= pulses= cells= first_x1_share= steady_x1_share=`.
void run_plant_family_ceiling(const PlantFamilyOptions& options, const grid::ParallelSession& session);

}  // namespace dynweigh::tools
