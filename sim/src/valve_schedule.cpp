#include "dynweigh/sim/valve_schedule.hpp"

#include <algorithm>
#include <cctype>
#include <stdexcept>

namespace dynweigh::sim {

std::vector<ScheduledCommand> parse_valve_schedule(const std::string& text) {
  std::vector<ScheduledCommand> events;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, comma - start);
    start = comma + 1;
    if (item.empty()) {
      if (comma == text.size()) break;
      throw std::invalid_argument("schedule: empty item");
    }
    const std::size_t at = item.find('@');
    if (at == std::string::npos) throw std::invalid_argument("schedule item '" + item + "': expected open@N, half@N or close@N");
    const std::string what = item.substr(0, at), when = item.substr(at + 1);
    ValveCommand command;
    if (what == "open") command = ValveCommand::open;
    else if (what == "half") command = ValveCommand::half;
    else if (what == "close" || what == "closed") command = ValveCommand::closed;
    else throw std::invalid_argument("schedule item '" + item + "': unknown valve state '" + what + "'");
    if (when.empty() || when.size() > 9 || !std::all_of(when.begin(), when.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); })) {
      throw std::invalid_argument("schedule item '" + item + "': the jiffy must be a whole number");
    }
    events.push_back({static_cast<std::uint32_t>(std::stoul(when)), command});
  }
  std::stable_sort(events.begin(), events.end(),
                   [](const ScheduledCommand& a, const ScheduledCommand& b) { return a.jiffy < b.jiffy; });
  return events;
}

}  // namespace dynweigh::sim
