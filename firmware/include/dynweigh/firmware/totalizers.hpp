#pragma once
// The totalizers beside the statistics: mass delivered, valve cycles and time dosing, counted
// since start-up or the last `stats reset` (RAM: a restart starts them again; the logbook keeps the
// fills themselves).
#include <cstdint>

#include "dynweigh/firmware/io.hpp"

namespace dynweigh::firmware {

struct Totalizers {
  float total_g = 0.0f;
  std::uint32_t valve_cycles = 0;    // the dosing valve opened from closed
  std::uint32_t gate_cycles = 0;     // the discharge gate opened from closed
  std::uint32_t dosing_jiffies = 0;  // a dose or a top-up running
  std::uint32_t after_sequence = 0;  // the statistics read logbook records after this one

  void jiffy(ValveCommand before, ValveCommand now, bool dosing) {
    if (before == ValveCommand::closed && now != ValveCommand::closed) ++valve_cycles;
    if (dosing) ++dosing_jiffies;
  }
};

}  // namespace dynweigh::firmware
