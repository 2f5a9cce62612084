#pragma once
// The plant family's speed comparison (docs/plant-family.md): how often the model strategy is faster
// than the baselines in the run, per plant x target cell, by the time / t_phys of its fills and
// the steady class they reach. Three readings:
// - faster: a lower time than every baseline at an equal or better class than every baseline's
//   (X(0.5) is worse than X(0.2));
// - faster within X(1): the same with every class better than the X(1) the model was asked for
//   taken as X(1), so that a baseline's X(0.2) does not outweigh a model that met what was asked
//   in less time;
// - unbeaten: the model reached a class and no baseline reached an equal or better one in at most
//   its time (a faster baseline of a worse class does not count against it).
// Host code.
#include <optional>
#include <string>
#include <vector>

namespace dynweigh::tools {

// The strategies a family run compares the model against: every one but the model, its learning
// variant and the oracles.
bool is_family_baseline(const std::string& strategy);

// From the run's cell lines (`strategy= plant= target_g= ... class_steady= time_ratio= ...`): the
// line `summary comparison=model baselines=a,b cells=N faster_cells=K faster_share=F
// faster_cells_x1=K1 faster_share_x1=F1 unbeaten_cells=U unbeaten_share=G`, or nothing when the
// run has no model or no baseline.
std::optional<std::string> family_comparison_summary(const std::vector<std::string>& cell_lines);

}  // namespace dynweigh::tools
