#pragma once
// Lines for the in-process plant rather than the indicator, on dynweigh-fw's stdio console: an
// operator at the simulated plant looks into the silo and calls for material from upstream.
//   plant               -> PLANT silo_kg= refilled_kg= refilling= in_flight_kg= container_kg=
//                          discharged_kg= gate=<0 closed|1 moving|3 open>
//   plant refill        -> the feeder refills the silo to its fill level at the scene's rate
//   plant refill <kg>   -> <kg> poured into the silo at once
// Each answer ends in OK, or ERR 2 for a bad line, as the indicator's commands do.
#include <string>

#include "dynweigh/sim/plant.hpp"

namespace dynweigh::tools {

// True when `line` is a plant command; `answer` then holds its whole answer, one line each ending
// in '\n'. Other lines are the indicator's.
bool answer_plant_command(const std::string& line, sim::Plant& plant, std::string& answer);

}  // namespace dynweigh::tools
