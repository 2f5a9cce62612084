#pragma once
// The console's commands: one table (console_commands.cpp) whose usage lines `help` prints, and the
// handlers grouped by what they act on: the dose and its result (dosing_commands.cpp,
// fill_conclusion.cpp), the test data (test_data_commands.cpp), the scale (scale_commands.cpp), the
// settings (settings_commands.cpp), the logbook (logbook_commands.cpp), the materials (material_commands.cpp). A friend of the Indicator:
// the handlers act on its parts, and its own API stays the step.
#include <cstddef>

#include "dynweigh/firmware/indicator.hpp"

namespace dynweigh::firmware {

struct CommandArguments {
  static constexpr std::size_t kMax = 2 + BatchCycle::kMaxIngredients;  // `batch`, its ingredients, a strategy
  const char* word[kMax];
  std::size_t count;  // kMax + 1: more words than any command takes
};

struct ConsoleCommands {
  using Arguments = CommandArguments;
  using Handler = void (*)(Indicator&, const Arguments&);

  // Runs the line's command, or answers why not. `line` is split in place.
  static void run(Indicator& indicator, char* line);

  // Strict integer: optional sign, digits only, within [minimum, maximum].
  static bool parse_int(const char* text, long minimum, long maximum, long& value);
  // Strict decimal: [-]digits[.digits], no exponent, no junk.
  static bool parse_decimal(const char* text, float& value);

  // The indicator's own (console_commands.cpp).
  static void status(Indicator& indicator, const Arguments& args);
  static void help(Indicator& indicator, const Arguments& args);
  static void version(Indicator& indicator, const Arguments& args);
  // The dose, the valve, and the dose's result (dosing_commands.cpp, fill_conclusion.cpp).
  static void dose(Indicator& indicator, const Arguments& args);
  static void valve(Indicator& indicator, const Arguments& args);
  static void abort(Indicator& indicator, const Arguments& args);
  static void estimates(Indicator& indicator, const Arguments& args);
  static void accept(Indicator& indicator, const Arguments& args);
  static void topup(Indicator& indicator, const Arguments& args);
  // The discharge gate (discharge_commands.cpp).
  static void discharge(Indicator& indicator, const Arguments& args);
  // A batch of ingredients into one hopper (batch_commands.cpp).
  static void batch(Indicator& indicator, const Arguments& args);
  // The test data (test_data_commands.cpp).
  static void starttestdata(Indicator& indicator, const Arguments& args);
  static void readtestdata(Indicator& indicator, const Arguments& args);
  // The scale (scale_commands.cpp).
  static void tare(Indicator& indicator, const Arguments& args);
  static void zero(Indicator& indicator, const Arguments& args);
  static void cal(Indicator& indicator, const Arguments& args);
  static void clearfault(Indicator& indicator, const Arguments& args);
  // The settings (settings_commands.cpp).
  static void param(Indicator& indicator, const Arguments& args);
  static void learn(Indicator& indicator, const Arguments& args);
  // The logbook (logbook_commands.cpp).
  static void log(Indicator& indicator, const Arguments& args);
  // The material table and each material's statistics (material_commands.cpp).
  static void material(Indicator& indicator, const Arguments& args);
  static void stats(Indicator& indicator, const Arguments& args);
};

}  // namespace dynweigh::firmware
