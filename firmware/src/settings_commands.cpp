// The settings on the console: `param` (the parameters.hpp table) and `learn` (what the learning
// strategies keep). A change persists: its OK waits for the board's save.
#include <cstring>

#include "console_commands.hpp"

namespace dynweigh::firmware {
namespace {

// LEARN target_bucket=255 fall_bucket=255 flow_bucket=255 correction_g=<at most 50 g x 65535 fills> fills=65535
constexpr std::size_t kLearnLineMaxBytes = 6 + 17 + 16 + 16 + 24 + 12 + 1;
static_assert(LearningTable::kEntries * kLearnLineMaxBytes + 3 <= Console::kLongestAnswerBytes,
              "the learn listing outgrew the console's room for an answer");

void write_parameter(Console& out, const Parameters& parameters, ParameterId id) {
  const ParameterSpec& spec = parameter_spec(id);
  out.write(spec.name);
  out.put('=');
  if (spec.choices) {
    out.write(spec.choices[static_cast<int>(parameters.get(id))]);
  } else {
    out.write_decimal(parameters.get(id), 3);
  }
}

}  // namespace

void ConsoleCommands::param(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  Parameters& parameters = indicator.settings_.parameters;
  if (args.count == 1) {
    for (std::size_t i = 0; i < kParameterCount; ++i) {
      const auto id = static_cast<ParameterId>(i);
      write_parameter(console, parameters, id);
      console.write("  # ");
      console.line(parameter_spec(id).description);
    }
    return indicator.ok();
  }
  if (args.count > 3) return console.error(2, "usage: param [<name> [<value>]]");
  const ParameterId id = find_parameter(args.word[1]);
  if (id == ParameterId::count) return console.error(2, "unknown parameter");
  if (args.count == 3) {
    const ParameterSpec& spec = parameter_spec(id);
    if (spec.read_only) return console.error(2, "read-only");
    if (indicator.reject_if_busy()) return;
    float value = -1.0f;
    for (std::uint8_t c = 0; spec.choices && c < spec.choice_count; ++c) {
      if (std::strcmp(spec.choices[c], args.word[2]) == 0) value = float(c);
    }
    if (!spec.choices && !parse_decimal(args.word[2], value)) return console.error(2, "not a number");
    if (!parameters.set(id, value)) return console.error(2, "value out of range");
    indicator.settings_.materials.follow_parameter(id, parameters);  // density, class: the selected material's
    indicator.apply_parameters();
    indicator.settings_changed_ = true;
  }
  write_parameter(console, parameters, id);
  console.put('\n');
  indicator.ok();
}

void ConsoleCommands::learn(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  if (args.count == 2 && std::strcmp(args.word[1], "reset") == 0) {
    if (indicator.reject_if_busy()) return;
    indicator.settings_.learning.reset();
    indicator.settings_.baselines = BaselineLearning{};
    indicator.settings_.materials.forget_learned();
    indicator.settings_changed_ = true;
    return indicator.ok();
  }
  if (args.count != 1) return console.error(2, "usage: learn [reset]");
  for (std::size_t i = 0; i < LearningTable::kEntries; ++i) {
    const LearningTable::Entry& e = indicator.settings_.learning.entry(i);
    if (!e.used) continue;
    console.write("LEARN target_bucket=");
    console.write_int(e.key.target_bucket);
    console.write(" fall_bucket=");
    console.write_int(e.key.fall_bucket);
    console.write(" flow_bucket=");
    console.write_int(e.key.flow_bucket);
    console.write(" correction_g=");
    console.write_decimal(e.correction_g, 1);
    console.write(" fills=");
    console.write_int(e.fills);
    console.put('\n');
  }
  indicator.ok();
}

}  // namespace dynweigh::firmware
