// The logbook on the console: `log [<n>]` and `log <from> <to>`, one LOG line a record, oldest
// first, printed a few lines a jiffy as the console ring drains.
#include <cstdlib>
#include <cstring>

#include "console_commands.hpp"

namespace dynweigh::firmware {
namespace {

// LOG seq= jiffy= material= target= final= tolerance= topups= crc=ok, every number at its widest.
constexpr std::size_t kLogLineMaxBytes = 4 + 15 + 17 + 13 + 19 + 18 + 20 + 11 + 7 + 1;
constexpr std::uint32_t kDefaultLogLines = 10;

bool parse_sequence(const char* text, std::uint32_t& value) {
  if (!text || !*text || std::strlen(text) > 10) return false;
  char* end = nullptr;
  const unsigned long parsed = std::strtoul(text, &end, 10);
  if (*end != '\0' || *text == '-' || *text == '+' || parsed > 0xFFFFFFFFul) return false;
  value = std::uint32_t(parsed);
  return true;
}

// Grams from tenths: whole grams as integers, as RESULT prints them.
void write_grams(Console& out, std::int32_t tenths) {
  if (tenths % 10 == 0) {
    out.write_int(tenths / 10);
  } else {
    out.write_decimal(float(tenths) / 10.0f, 1);
  }
}

}  // namespace

void ConsoleCommands::log(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  if (args.count > 3) return console.error(2, "usage: log [<n>] | log <from> <to>");
  if (!indicator.logbook_ || !indicator.logbook_->usable()) return console.error(2, "no logbook");
  if (indicator.reject_if_busy()) return;
  const std::uint32_t first = indicator.logbook_->first_sequence(), last = indicator.logbook_->last_sequence();
  std::uint32_t from = 0, to = 0;
  if (args.count == 3) {
    if (!parse_sequence(args.word[1], from) || !parse_sequence(args.word[2], to) || from > to) {
      return console.error(2, "need <from> <= <to>");
    }
  } else {
    std::uint32_t n = kDefaultLogLines;
    if (args.count == 2 && (!parse_sequence(args.word[1], n) || n == 0)) return console.error(2, "usage: log [<n>]");
    to = last;
    from = last >= n ? last - n + 1 : 1;
  }
  if (from < first) from = first;
  if (to > last) to = last;
  if (last == 0 || from > to) return indicator.ok();  // nothing kept in that range
  indicator.log_print_ = Indicator::LogPrint{true, from, to};
}

void Indicator::continue_log_print() {
  while (log_print_.active && console_.free_space() >= kLogLineMaxBytes) {
    if (log_print_.next > log_print_.last) {
      log_print_.active = false;
      ok();
      return;
    }
    const std::uint32_t sequence = log_print_.next++;
    LogRecord r;
    console_.write("LOG seq=");
    console_.write_int(sequence);
    if (!logbook_->read(sequence, r)) {
      console_.line(" crc=bad");
      continue;
    }
    console_.write(" jiffy=");
    console_.write_int(r.jiffy);
    console_.write(" material=");
    console_.write_int(r.material);
    console_.write(" target=");
    write_grams(console_, r.target_dg);
    console_.write(" final=");
    write_grams(console_, r.final_dg);
    console_.write(" tolerance=");
    console_.write(tolerance_verdict_name(r.tolerance));
    console_.write(" topups=");
    console_.write_int(r.topups);
    console_.line(" crc=ok");
  }
}

}  // namespace dynweigh::firmware
