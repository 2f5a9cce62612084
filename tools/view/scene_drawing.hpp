#pragma once
// The plant as the live view draws it, to scale: the silo with its sand level, the valve, the
// falling stream, the pile growing in the container on the scale.
#include "dynweigh/sim/plant.hpp"
#include "force_trace.hpp"

namespace dynweigh::tools {

// What the stream needs beyond the plant's truth: when the valve last opened and closed, so the
// stream's front falls from the orifice after opening and its tail after closing.
struct StreamTimes {
  double opened_s = -1.0;
  double closed_s = -1.0;
};

void draw_plant(const sim::Plant& plant, const StreamTimes& times, const Rect& area);

}  // namespace dynweigh::tools
