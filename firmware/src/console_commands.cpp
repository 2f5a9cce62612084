// The console's command table (docs/console.md): each command is declared beside its usage, so
// `help` and the dispatcher read the same table. The handlers of the indicator's own state are here;
// the others beside the part they act on (console_commands.hpp).
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "console_commands.hpp"
#include "dynweigh/firmware/decimal_fraction.hpp"

namespace dynweigh::firmware {
namespace {

struct CommandSpec {
  const char* name;
  const char* usage;
  ConsoleCommands::Handler handler;
};

constexpr CommandSpec kCommands[] = {
    {"starttestdata", "starttestdata [<open> <close>]  1000-jiffy test cycle, valve schedule in jiffies",
     &ConsoleCommands::starttestdata},
    {"readtestdata", "readtestdata [info]  print the last cycle: <jiffy> <raw> <filtered> <marker>; info: whose",
     &ConsoleCommands::readtestdata},
    {"dose", "dose <grams> [model|preact|twostage|learn|pac|flowpreact]  one dosing cycle to the target",
     &ConsoleCommands::dose},
    {"tare", "tare  take the present weight as tare", &ConsoleCommands::tare},
    {"zero", "zero  at standstill: zero-setting within 4 % of Max, else adjustment (then cal) (persists)",
     &ConsoleCommands::zero},
    {"cal", "cal <grams>  at standstill: span adjustment with a test weight on the zeroed scale (persists)",
     &ConsoleCommands::cal},
    {"status", "status  state (idle dosing settling hold discharging fault), weight (none: no sample or not calibrated), valve and fault",
     &ConsoleCommands::status},
    {"param", "param [<name> [<value>]]  list, read or set a parameter (persists)",
     &ConsoleCommands::param},
    {"valve", "valve <0|1|2>  manual valve: closed, half, open (when idle)", &ConsoleCommands::valve},
    {"clearfault", "clearfault  clear a latched fault", &ConsoleCommands::clearfault},
    {"abort", "abort  stop the dose, test cycle or zero/cal in progress: valve closed at once", &ConsoleCommands::abort},
    {"learn", "learn [reset]  the learn strategy's corrections: list, or forget them and what pac and flowpreact learned "
     "(persists)",
     &ConsoleCommands::learn},
    {"estimates", "estimates  what the last model dose measured (first impact, dead time, flow, impulse) and the material learned",
     &ConsoleCommands::estimates},
    {"accept", "accept  take the held result as it is (logged with its tolerance verdict)", &ConsoleCommands::accept},
    {"topup", "topup  a top-up pulse for the held result under its target, then judged again", &ConsoleCommands::topup},
    {"discharge", "discharge  empty the hopper through the gate (open, empty and stable, closed: proven)",
     &ConsoleCommands::discharge},
    {"batch", "batch <m>:<g> [<m>:<g> ...] [<strategy>]  up to 8 ingredients into the hopper, material m from valve m (0..7)",
     &ConsoleCommands::batch},
    {"log", "log [<n>] | log <from> <to>  the logbook: the last n results (10), or by sequence number", &ConsoleCommands::log},
    {"material", "material [<n> [name <s> | density <kg/m^3> | class <x>]]  list, select (n 0..15) or edit the "
     "materials (persists)",
     &ConsoleCommands::material},
    {"stats", "stats [<n>] | stats reset [<n>]  a material's last 100 fills and totalizers (default: the selected)",
     &ConsoleCommands::stats},
    {"help", "help  this list", &ConsoleCommands::help},
    {"version", "version  firmware version", &ConsoleCommands::version},
};

constexpr std::size_t help_bytes() {
  std::size_t bytes = 3;  // OK
  for (const CommandSpec& command : kCommands) {
    std::size_t n = 0;
    while (command.usage[n]) ++n;
    bytes += n + 1;
  }
  return bytes;
}
static_assert(help_bytes() <= Console::kLongestAnswerBytes, "help outgrew the console's room for an answer");

CommandArguments split(char* line) {
  CommandArguments args{{}, 0};
  char* p = line;
  while (*p) {
    while (*p == ' ' || *p == '\t') *p++ = '\0';
    if (!*p) break;
    if (args.count == CommandArguments::kMax) {
      args.count = CommandArguments::kMax + 1;  // too many: the handler's count check fails
      break;
    }
    args.word[args.count++] = p;
    while (*p && *p != ' ' && *p != '\t') ++p;
  }
  return args;
}

}  // namespace

bool ConsoleCommands::parse_int(const char* text, long minimum, long maximum, long& value) {
  if (!text || !*text) return false;
  char* end = nullptr;
  const long parsed = std::strtol(text, &end, 10);
  if (*end != '\0' || parsed < minimum || parsed > maximum) return false;
  if (std::strlen(text) > 12) return false;  // strtol saturates silently on huge inputs
  value = parsed;
  return true;
}

bool ConsoleCommands::parse_decimal(const char* text, float& value) {
  if (!text || !*text) return false;
  const char* p = text;
  bool negative = false;
  if (*p == '-' || *p == '+') negative = *p++ == '-';
  std::uint64_t numerator = 0;  // the digits, point removed
  int decimals = 0;
  bool digits = false, point = false, more_digits = false;
  for (; *p; ++p) {
    if (*p == '.' && !point) {
      point = true;
    } else if (*p >= '0' && *p <= '9') {
      digits = true;
      const unsigned digit = unsigned(*p - '0');
      if (!point) {
        numerator = numerator * 10 + digit;
        if (numerator > 1000000000000u) return false;
      } else if (numerator < 100000000000000000u) {
        numerator = numerator * 10 + digit;
        ++decimals;
      } else {
        more_digits = more_digits || digit != 0;
      }
    } else {
      return false;
    }
  }
  if (!digits) return false;
  const float magnitude = nearest_float(numerator, decimals, more_digits);
  value = negative ? -magnitude : magnitude;
  return true;
}

void ConsoleCommands::run(Indicator& indicator, char* line) {
  const Arguments args = split(line);
  if (args.count == 0) return;
  for (const CommandSpec& command : kCommands) {
    if (std::strcmp(command.name, args.word[0]) == 0) return command.handler(indicator, args);
  }
  indicator.console_.error(1, "unknown command");
}

void ConsoleCommands::status(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  if (args.count != 1) return console.error(2, "usage: status");
  console.write("STATUS state=");
  console.write(Indicator::activity_name(indicator.activity()));
  console.write(" weight=");
  if (indicator.weight_known()) {
    console.write_int(std::lround(indicator.filtered_weight_g()));
  } else {
    console.write("none");
  }
  console.write(" valve=");
  console.write_int(static_cast<int>(indicator.valve_));
  console.write(" fault=");
  console.line(fault_name(indicator.fault_));
  indicator.ok();
}

void ConsoleCommands::help(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  if (args.count != 1) return console.error(2, "usage: help");
  for (const CommandSpec& command : kCommands) console.line(command.usage);
  indicator.ok();
}

void ConsoleCommands::version(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  if (args.count != 1) return console.error(2, "usage: version");
  console.write("dynweigh ");
  console.line(kFirmwareVersion);
  indicator.ok();
}

}  // namespace dynweigh::firmware
