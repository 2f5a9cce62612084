// The material table and each material's statistics on the console: `material` (list, select,
// edit) and `stats` (the last fills from the logbook, and the totalizers). A change of the table
// persists with the settings: its OK waits for the board's save.
#include <cstring>

#include "console_commands.hpp"
#include "dynweigh/firmware/fill_statistics.hpp"

namespace dynweigh::firmware {
namespace {

// MATERIAL n=15 name=<15> density=<5000.000> class=<100.000> fills=<u32> selected=1
constexpr std::size_t kMaterialLineMaxBytes = 8 + 5 + 6 + 15 + 9 + 8 + 7 + 7 + 7 + 10 + 11 + 1;
static_assert(MaterialTable::kMaterials * kMaterialLineMaxBytes + 3 <= Console::kLongestAnswerBytes,
              "the material listing outgrew the console's room for an answer");
constexpr std::uint32_t kLastFills = 100;

bool parse_material(const char* text, std::size_t& n) {
  long value = 0;
  if (!ConsoleCommands::parse_int(text, 0, long(MaterialTable::kMaterials) - 1, value)) return false;
  n = std::size_t(value);
  return true;
}

void write_material(Console& out, const MaterialTable& table, std::size_t n, const Totalizers& totals) {
  const Material& m = table.at(n);
  out.write("MATERIAL n=");
  out.write_int(std::int64_t(n));
  out.write(" name=");
  out.write(m.name);
  out.write(" density=");
  out.write_decimal(m.density, 3);
  out.write(" class=");
  out.write_decimal(m.class_x, 3);
  out.write(" fills=");
  out.write_int(totals.fills);
  out.write(" selected=");
  out.write_int(table.selected() == n ? 1 : 0);
  out.put('\n');
}

// Grams as kilograms with three decimals, in integers: a float would round a plant's years of fills.
void write_kilograms(Console& out, std::uint64_t grams) {
  out.write_int(std::int64_t(grams / 1000));
  out.put('.');
  const auto rest = std::uint32_t(grams % 1000);
  out.put(char('0' + rest / 100));
  out.put(char('0' + rest / 10 % 10));
  out.put(char('0' + rest % 10));
}

}  // namespace

void ConsoleCommands::material(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  MaterialTable& table = indicator.settings_.materials;
  Parameters& parameters = indicator.settings_.parameters;
  if (args.count == 1) {
    for (std::size_t n = 0; n < MaterialTable::kMaterials; ++n) {
      if (table.at(n).defined) write_material(console, table, n, indicator.totals_.material[n]);
    }
    return indicator.ok();
  }
  if (args.count != 2 && args.count != 4) {
    return console.error(2, "usage: material [<n> [name <s> | density <kg/m^3> | class <x>]]");
  }
  std::size_t n = 0;
  if (!parse_material(args.word[1], n)) return console.error(2, "material number 0..15");
  if (indicator.reject_if_busy()) return;
  if (args.count == 2) {
    table.select(n, parameters);
  } else if (std::strcmp(args.word[2], "name") == 0) {
    if (!table.rename(n, args.word[3])) return console.error(2, "name: 1..15 of A-Z a-z 0-9 _ - .");
  } else if (std::strcmp(args.word[2], "density") == 0 || std::strcmp(args.word[2], "class") == 0) {
    const bool density = args.word[2][0] == 'd';
    float value = 0.0f;
    if (!parse_decimal(args.word[3], value)) return console.error(2, "not a number");
    if (!(density ? table.set_density(n, value) : table.set_class(n, value))) {
      return console.error(2, "value out of range");
    }
    // The selected material's density and class are the parameters in force.
    if (n == table.selected()) table.select(n, parameters);
  } else {
    return console.error(2, "usage: material <n> name <s> | density <kg/m^3> | class <x>");
  }
  indicator.apply_parameters();
  indicator.settings_changed_ = true;
  write_material(console, table, n, indicator.totals_.material[n]);
  indicator.ok();
}

// `stats [<n>]`, `stats reset [<n>]`: material n's, by default the selected one's.
void ConsoleCommands::stats(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  const bool reset = args.count >= 2 && std::strcmp(args.word[1], "reset") == 0;
  const std::size_t number_at = reset ? 2 : 1;
  std::size_t n = indicator.settings_.materials.selected();
  if (args.count > number_at + 1 || (args.count == number_at + 1 && !parse_material(args.word[number_at], n))) {
    return console.error(2, "usage: stats [<n>] | stats reset [<n>]  (n 0..15)");
  }
  Totalizers& totals = indicator.totals_.material[n];
  if (reset) {
    if (indicator.reject_if_busy()) return;
    totals = Totalizers{};
    totals.after_sequence = indicator.logbook_ ? indicator.logbook_->last_sequence() : 0;
    if (!indicator.save_totals()) {
      indicator.raise(Fault::nvm_error);
      return console.error(4, "fault nvm_error");
    }
    return indicator.ok();
  }
  const FillStatistics s = indicator.logbook_
                               ? fill_statistics(*indicator.logbook_, std::uint8_t(n), totals.after_sequence, kLastFills)
                               : FillStatistics{};
  console.write("STATS material=");
  console.write_int(std::int64_t(n));
  console.write(" count=");
  console.write_int(s.count);
  console.write(" mean_g=");
  console.write_decimal(s.mean_g, 2);
  console.write(" sd_g=");
  console.write_decimal(s.sd_g, 2);
  console.write(" min_g=");
  console.write_decimal(s.min_g, 1);
  console.write(" max_g=");
  console.write_decimal(s.max_g, 1);
  console.write(" class=");
  console.write_decimal(s.class_x, 1);
  console.write(" total_kg=");
  write_kilograms(console, totals.total_g);
  console.write(" valve_cycles=");
  console.write_int(totals.valve_cycles);
  console.write(" gate_cycles=");
  console.write_int(totals.gate_cycles);
  console.write(" dosing_s=");
  console.write_decimal(float(totals.dosing_jiffies) * indicator.settings_.parameters.get(ParameterId::jiffy_ms) / 1000.0f, 2);
  console.put('\n');
  indicator.ok();
}

}  // namespace dynweigh::firmware
