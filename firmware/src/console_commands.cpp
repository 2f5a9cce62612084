// The console's command table (docs/console.md) and handlers: each command is declared beside its usage,
// so `help` and the dispatcher read the same table.
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "dynweigh/firmware/decimal_fraction.hpp"
#include "dynweigh/firmware/indicator.hpp"

namespace dynweigh::firmware {
namespace {

struct CommandSpec {
  const char* name;
  const char* usage;
  void (Indicator::*handler)(const Indicator::Arguments&);
};

constexpr CommandSpec kCommands[] = {
    {"starttestdata", "starttestdata [<open> <close>]  1000-jiffy test cycle, valve schedule in jiffies",
     &Indicator::command_starttestdata},
    {"readtestdata", "readtestdata [info]  print the last cycle: <jiffy> <raw> <filtered> <marker>; info: whose",
     &Indicator::command_readtestdata},
    {"dose", "dose <grams> [model|preact|twostage|learn|pac|flowpreact]  one dosing cycle to the target",
     &Indicator::command_dose},
    {"tare", "tare  take the present weight as tare", &Indicator::command_tare},
    {"zero", "zero  at standstill: zero-setting within 4 % of Max, else adjustment (then cal) (persists)",
     &Indicator::command_zero},
    {"cal", "cal <grams>  at standstill: span adjustment with a test weight on the zeroed scale (persists)",
     &Indicator::command_cal},
    {"status", "status  state (idle dosing settling hold fault), weight (none: no sample or not calibrated), valve and fault",
     &Indicator::command_status},
    {"param", "param [<name> [<value>]]  list, read or set a parameter (persists)",
     &Indicator::command_param},
    {"valve", "valve <0|1|2>  manual valve: closed, half, open (when idle)", &Indicator::command_valve},
    {"clearfault", "clearfault  clear a latched fault", &Indicator::command_clearfault},
    {"abort", "abort  stop the dose, test cycle or zero/cal in progress: valve closed at once", &Indicator::command_abort},
    {"learn", "learn [reset]  the learn strategy's corrections: list, or forget them and what pac and flowpreact learned "
     "(persists)",
     &Indicator::command_learn},
    {"estimates", "estimates  what the last model dose measured: first impact, dead time, flow, impulse",
     &Indicator::command_estimates},
    {"accept", "accept  take the held result as it is (logged with its tolerance verdict)", &Indicator::command_accept},
    {"topup", "topup  a top-up pulse for the held result under its target, then judged again", &Indicator::command_topup},
    {"log", "log [<n>] | log <from> <to>  the logbook: the last n results (10), or by sequence number", &Indicator::command_log},
    {"stats", "stats [0] | stats reset  the material's last 100 fills and the totalizers", &Indicator::command_stats},
    {"help", "help  this list", &Indicator::command_help},
    {"version", "version  firmware version", &Indicator::command_version},
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
static_assert(help_bytes() <= Indicator::kLongestAnswerBytes, "help outgrew the console's room for an answer");

// LEARN target_bucket=255 fall_bucket=255 flow_bucket=255 correction_g=<at most 50 g x 65535 fills> fills=65535
constexpr std::size_t kLearnLineMaxBytes = 6 + 17 + 16 + 16 + 24 + 12 + 1;
static_assert(LearningTable::kEntries * kLearnLineMaxBytes + 3 <= Indicator::kLongestAnswerBytes,
              "the learn listing outgrew the console's room for an answer");

// Strict integer: optional sign, digits only, within [minimum, maximum].
bool parse_int(const char* text, long minimum, long maximum, long& value) {
  if (!text || !*text) return false;
  char* end = nullptr;
  const long parsed = std::strtol(text, &end, 10);
  if (*end != '\0' || parsed < minimum || parsed > maximum) return false;
  if (std::strlen(text) > 12) return false;  // strtol saturates silently on huge inputs
  value = parsed;
  return true;
}

// Strict decimal: [-]digits[.digits], no exponent, no junk.
bool parse_decimal(const char* text, float& value) {
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

Indicator::Arguments split(char* line) {
  Indicator::Arguments args{{}, 0};
  char* p = line;
  while (*p) {
    while (*p == ' ' || *p == '\t') *p++ = '\0';
    if (!*p) break;
    if (args.count == Indicator::Arguments::kMax) {
      args.count = Indicator::Arguments::kMax + 1;  // too many: the handler's count check fails
      break;
    }
    args.word[args.count++] = p;
    while (*p && *p != ' ' && *p != '\t') ++p;
  }
  return args;
}

}  // namespace

void Indicator::execute(char* line) {
  const Arguments args = split(line);
  if (args.count == 0) return;
  for (const CommandSpec& command : kCommands) {
    if (std::strcmp(command.name, args.word[0]) == 0) {
      (this->*command.handler)(args);
      return;
    }
  }
  error(1, "unknown command");
}

void Indicator::command_starttestdata(const Arguments& args) {
  if (args.count != 1 && args.count != 3) return error(2, "usage: starttestdata [<open> <close>]");
  long open = 0, close = 0;
  if (args.count == 3 && (!parse_int(args.word[1], 0, 1000, open) || !parse_int(args.word[2], 0, 1000, close) ||
                          open > close)) {
    return error(2, "need 0 <= open <= close <= 1000");
  }
  if (reject_if_busy()) return;
  if (fault_ != Fault::none && args.count == 3) return error(4, "fault active");
  test_ = TestCycle{true, args.count == 3, 0, std::uint32_t(open), std::uint32_t(close)};
  recorder_.start();
  recording_source_ = RecordingSource{};
  ok();
}

void Indicator::command_readtestdata(const Arguments& args) {
  const bool info = args.count == 2 && std::strcmp(args.word[1], "info") == 0;
  if (args.count != 1 && !info) return error(2, "usage: readtestdata [info]");
  if (info) {
    if (!recorder_.has_data()) return error(2, "no test data");
    console_.write("TESTDATA cycle=");
    if (recording_source_.dose) {
      console_.write("dose dose=");
      console_.write_int(recording_source_.dose_number);
      console_.write(" target=");
      console_.write_int(recording_source_.target_g);
      console_.write(" strategy=");
      console_.write(strategy_name(recording_source_.strategy));
    } else {
      console_.write("starttestdata");
    }
    console_.write(" records=");
    console_.write_int(std::int64_t(recorder_.count()));
    console_.put('\n');
    return ok();
  }
  if (reject_if_busy()) return;
  if (!recorder_.has_data()) return error(2, "no test data");
  // A dose's recording still running after its result: the print waits for its 1000 records.
  printing_ = true;
  print_index_ = 0;
}

void Indicator::command_dose(const Arguments& args) {
  const Parameters& p = settings_.parameters;
  long target = 0;
  DosingStrategy strategy = DosingStrategy::model;
  if (args.count < 2 || args.count > 3) return error(2, "usage: dose <grams> [<strategy>]");
  if (!parse_int(args.word[1], 1, long(p.get(ParameterId::capacity_g)), target)) {
    return error(2, "target out of range");
  }
  if (args.count == 3 && !parse_strategy(args.word[2], strategy)) return error(2, "unknown strategy");
  if (!strategy_available(strategy)) return error(2, "strategy not in this build");
  if (reject_if_busy()) return;
  // A dose owns the valve and ends with it closed; started over a manually opened valve, the
  // manual command would open it again after the result (found by fuzz/console_fuzzer.cpp).
  if (manual_valve_ != ValveCommand::closed) return error(3, "valve open (valve 0 first)");
  if (fault_ != Fault::none) return error(4, "fault active");
  if (!settings_.calibration.valid()) return error(5, "not calibrated");
  if (filtered_weight_g() + tare_g_ + float(target) > p.get(ParameterId::capacity_g)) {
    return error(2, "target exceeds the scale's capacity");
  }
  dosing_.restore_baselines(settings_.baselines);
  dosing_.start(std::int32_t(target), strategy, &settings_.learning);
  dose_command_pending_ = true;
  recorder_.start();
  recording_source_ = RecordingSource{true, ++doses_started_, std::int32_t(target), strategy};
}

void Indicator::command_tare(const Arguments& args) {
  if (args.count != 1) return error(2, "usage: tare");
  if (reject_if_busy()) return;
  if (!settings_.calibration.valid()) return error(5, "not calibrated");
  tare_g_ += filtered_weight_g();
  ok();
}

// `zero` and `cal` answer once the reading stands still (commissioning.cpp).
void Indicator::command_zero(const Arguments& args) {
  if (args.count != 1) return error(2, "usage: zero");
  if (reject_if_busy()) return;
  start_adjustment(Adjustment::Kind::zero, 0);
}

void Indicator::command_cal(const Arguments& args) {
  long grams = 0;
  if (args.count != 2) return error(2, "usage: cal <grams>");
  if (!parse_int(args.word[1], 1, long(settings_.parameters.get(ParameterId::capacity_g)), grams)) {
    return error(2, "load out of range");
  }
  if (reject_if_busy()) return;
  if (!settings_.calibration.zero_set) return error(5, "zero the empty scale first");
  start_adjustment(Adjustment::Kind::span, std::int32_t(grams));
}

void Indicator::command_status(const Arguments& args) {
  if (args.count != 1) return error(2, "usage: status");
  const ToleranceFollowUp::Phase follow_up = follow_up_.phase();
  const char* state = fault_ != Fault::none                                   ? "fault"
                      : follow_up == ToleranceFollowUp::Phase::holding        ? "hold"
                      : dosing_.phase() == DosingCycle::Phase::settling ||
                              follow_up == ToleranceFollowUp::Phase::settling ? "settling"
                      : dosing_.phase() == DosingCycle::Phase::dosing || test_.active ||
                              follow_up == ToleranceFollowUp::Phase::pulsing  ? "dosing"
                                                                              : "idle";
  console_.write("STATUS state=");
  console_.write(state);
  console_.write(" weight=");
  if (weight_known()) {
    console_.write_int(std::lround(filtered_weight_g()));
  } else {
    console_.write("none");
  }
  console_.write(" valve=");
  console_.write_int(static_cast<int>(valve_));
  console_.write(" fault=");
  console_.line(fault_name(fault_));
  ok();
}

namespace {
void write_parameter(TextWriter& out, const Parameters& parameters, ParameterId id) {
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

void Indicator::command_param(const Arguments& args) {
  Parameters& parameters = settings_.parameters;
  if (args.count == 1) {
    for (std::size_t i = 0; i < kParameterCount; ++i) {
      const auto id = static_cast<ParameterId>(i);
      write_parameter(console_, parameters, id);
      console_.write("  # ");
      console_.line(parameter_spec(id).description);
    }
    return ok();
  }
  if (args.count > 3) return error(2, "usage: param [<name> [<value>]]");
  const ParameterId id = find_parameter(args.word[1]);
  if (id == ParameterId::count) return error(2, "unknown parameter");
  if (args.count == 3) {
    const ParameterSpec& spec = parameter_spec(id);
    if (spec.read_only) return error(2, "read-only");
    if (reject_if_busy()) return;
    float value = -1.0f;
    for (std::uint8_t c = 0; spec.choices && c < spec.choice_count; ++c) {
      if (std::strcmp(spec.choices[c], args.word[2]) == 0) value = float(c);
    }
    if (!spec.choices && !parse_decimal(args.word[2], value)) return error(2, "not a number");
    if (!parameters.set(id, value)) return error(2, "value out of range");
    apply_parameters();
    settings_changed_ = true;
  }
  write_parameter(console_, parameters, id);
  console_.put('\n');
  ok();
}

void Indicator::command_valve(const Arguments& args) {
  long position = 0;
  if (args.count != 2 || !parse_int(args.word[1], 0, 2, position)) return error(2, "usage: valve <0|1|2>");
  if (reject_if_busy()) return;
  if (fault_ != Fault::none && position != 0) return error(4, "fault active");
  manual_valve_ = static_cast<ValveCommand>(position);
  ok();
}

void Indicator::command_clearfault(const Arguments& args) {
  if (args.count != 1) return error(2, "usage: clearfault");
  fault_ = Fault::none;
  stale_jiffies_ = 0;
  supervisor_.reset();  // a cause still present is found again from scratch
  filter_.restart();
  manual_valve_ = ValveCommand::closed;
  ok();
}

// The running command that abort cuts short answers ERR 3 aborted, before abort's own OK.
void Indicator::command_abort(const Arguments& args) {
  if (args.count != 1) return error(2, "usage: abort");
  if (dosing_.phase() != DosingCycle::Phase::idle) dosing_.abort();
  follow_up_.finish();  // a held or topping-up result is dropped, unlogged
  if (dose_command_pending_ || adjustment_.kind != Adjustment::Kind::none) {
    dose_command_pending_ = false;
    adjustment_.kind = Adjustment::Kind::none;
    error(3, "aborted");
  }
  test_.active = false;
  test_.scheduled = false;
  manual_valve_ = ValveCommand::closed;
  ok();
}

void Indicator::command_learn(const Arguments& args) {
  if (args.count == 2 && std::strcmp(args.word[1], "reset") == 0) {
    if (reject_if_busy()) return;
    settings_.learning.reset();
    settings_.baselines = BaselineLearning{};
    settings_changed_ = true;
    return ok();
  }
  if (args.count != 1) return error(2, "usage: learn [reset]");
  for (std::size_t i = 0; i < LearningTable::kEntries; ++i) {
    const LearningTable::Entry& e = settings_.learning.entry(i);
    if (!e.used) continue;
    console_.write("LEARN target_bucket=");
    console_.write_int(e.key.target_bucket);
    console_.write(" fall_bucket=");
    console_.write_int(e.key.fall_bucket);
    console_.write(" flow_bucket=");
    console_.write_int(e.key.flow_bucket);
    console_.write(" correction_g=");
    console_.write_decimal(e.correction_g, 1);
    console_.write(" fills=");
    console_.write_int(e.fills);
    console_.put('\n');
  }
  ok();
}

namespace {
void write_estimate(TextWriter& out, const char* key, bool known, float value, int decimals) {
  out.put(' ');
  out.write(key);
  out.put('=');
  if (known) {
    out.write_decimal(value, decimals);
  } else {
    out.write("none");
  }
}
}  // namespace

void Indicator::command_estimates(const Arguments& args) {
  if (args.count != 1) return error(2, "usage: estimates");
  const DoseEstimates<float>& e = dosing_.model_estimates();
  if (!e.impact_timed && !e.measured) return error(2, "no model dose measured yet");
  const auto& s = e.signature;
  console_.write("ESTIMATES");
  write_estimate(console_, "impact_ms", e.impact_timed, 1000.0f * e.first_impact_s, 1);
  write_estimate(console_, "dead_ms", e.impact_timed, 1000.0f * e.dead_time_s, 1);
  write_estimate(console_, "dead_used_ms", true, 1000.0f * dosing_.model_dead_time_s(), 1);
  write_estimate(console_, "stroke_used_ms", true, 1000.0f * dosing_.model_stroke_s(), 1);
  write_estimate(console_, "flow_kg_s", e.measured, e.flow_kg_s, 3);
  write_estimate(console_, "impulse_g", s.valid, 1000.0f * s.impulse_kg, 1);
  write_estimate(console_, "impact_m_s", s.valid, s.impact_speed_m_s, 2);
  write_estimate(console_, "outflow_m_s", s.valid, s.outflow_speed_m_s, 2);
  write_estimate(console_, "fall_mm", s.valid, 1000.0f * s.implied_fall_height_m, 0);
  console_.put('\n');
  ok();
}

void Indicator::command_help(const Arguments& args) {
  if (args.count != 1) return error(2, "usage: help");
  for (const CommandSpec& command : kCommands) console_.line(command.usage);
  ok();
}

void Indicator::command_version(const Arguments& args) {
  if (args.count != 1) return error(2, "usage: version");
  console_.write("dynweigh ");
  console_.line(kFirmwareVersion);
  ok();
}

}  // namespace dynweigh::firmware
