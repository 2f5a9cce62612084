#pragma once
// An open-loop valve schedule in jiffies (10 ms), written `open@50,half@400,close@600`, and the
// loop that runs a plant through it one jiffy at a time. Host-side: parsing may throw.
#include <cstdint>
#include <string>
#include <vector>

#include "dynweigh/sim/plant.hpp"

namespace dynweigh::sim {

inline constexpr double kJiffyS = 0.010;  // the indicator's jiffy

struct ScheduledCommand {
  std::uint32_t jiffy;
  ValveCommand command;
};

// Events sorted by jiffy; throws std::invalid_argument naming the bad item.
std::vector<ScheduledCommand> parse_valve_schedule(const std::string& text);

// What the loop hands out per jiffy: the truth and the sample at the jiffy's instant, after that
// jiffy's command has been applied, before the plant advances.
struct JiffyRecord {
  std::uint32_t jiffy;
  const PlantTruth& truth;
  LoadCellSample sample;
  ValveCommand command;
};

// Runs `jiffies` jiffies; `on_jiffy(const JiffyRecord&)` is called once for each.
template <typename OnJiffy>
void run_valve_schedule(Plant& plant, const std::vector<ScheduledCommand>& schedule, std::uint32_t jiffies,
                        OnJiffy&& on_jiffy) {
  std::size_t next = 0;
  ValveCommand command = ValveCommand::closed;
  for (std::uint32_t jiffy = 0; jiffy < jiffies; ++jiffy) {
    while (next < schedule.size() && schedule[next].jiffy <= jiffy) command = schedule[next++].command;
    plant.command_valve(command);
    const LoadCellSample sample = plant.sample();
    on_jiffy(JiffyRecord{jiffy, plant.truth(), sample, command});
    plant.advance(kJiffyS);
  }
}

}  // namespace dynweigh::sim
