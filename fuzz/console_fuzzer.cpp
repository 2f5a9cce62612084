// Fuzz target: arbitrary bytes on the indicator's serial console, through the same loop every board
// runs (hal::run_one_jiffy), against a toy plant so the commands run to their end. Each input is
// played twice: as a serial line delivers it (115 bytes a jiffy, typed ahead of the answers), and
// as `dynweigh-fw --console stdio` does (each line once the previous command has finished).
//
// Invariants, checked every jiffy:
//  - the valve is commanded open or half only after a line that can open it (`dose <g> ...`,
//    `valve 1|2`, `starttestdata <open> <close>`) has been received, and none since a fault or a
//    dose's RESULT with every line answered (a finished dose leaves the valve closed); never while
//    a fault is latched;
//  - the answer text is printable ASCII in lines of bounded length; no jiffy sends more than the
//    transmit ring holds; the valve delay byte stays within the 0..99 of docs/can-protocol.md;
//  - never more answers (`OK` or `ERR ...`) than command lines, and once the indicator is idle
//    again after the input, exactly one answer per command line;
//  - with `param echo 1`, a jiffy's text holds exactly the echo of what was typed (the line
//    reader's rules: characters, "\b \b" for an erasure, one newline a line end), with nothing but
//    whole answer lines at line starts before it, within it and after it.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/firmware/settings_slots.hpp"
#include "dynweigh/hal/control_loop.hpp"
#include "toy_plant.hpp"

namespace {

using namespace dynweigh;

// 115200 baud, 8N1: 11520 bytes/s, 115 in a 10 ms jiffy.
constexpr std::size_t kSerialBytesPerJiffy = 115;
// Room for a 50 kg dose at the toy plant's flow, its settling and a `readtestdata` print, per run.
constexpr std::uint32_t kMaxJiffies = 6000;
// The widest answer line: `estimates`' PULSES line with every field at its widest (a 500 mm bore
// at 5000 kg/m^3 flows about 1.6 t/s, its law's flow in g/s up to 9 characters, its loss 8, each
// travel 7), 186 characters.
constexpr std::size_t kMaxAnswerLine = 200;

[[noreturn]] void violated(const char* what, std::uint32_t jiffy) {
  std::fprintf(stderr, "console invariant violated at jiffy %u: %s\n", unsigned(jiffy), what);
  std::abort();
}

// What a command line asks for, as far as the invariants care.
struct LineMeaning {
  bool command = false;    // has a word: the indicator answers it
  bool can_open = false;   // may open the valve if accepted
};

LineMeaning meaning_of(const char* line) {
  char copy[firmware::ConsoleLineReader::kMaxLine + 1];
  std::strncpy(copy, line, sizeof copy - 1);
  copy[sizeof copy - 1] = '\0';
  const char* words[4] = {};
  std::size_t count = 0;
  for (char* token = std::strtok(copy, " \t"); token; token = std::strtok(nullptr, " \t")) {
    if (count < 4) words[count] = token;
    ++count;
  }
  LineMeaning m;
  m.command = count > 0;
  if (count == 0) return m;
  if (std::strcmp(words[0], "dose") == 0) m.can_open = count >= 2;
  if (std::strcmp(words[0], "valve") == 0) m.can_open = count == 2 && std::strcmp(words[1], "0") != 0;
  if (std::strcmp(words[0], "starttestdata") == 0) m.can_open = count == 3;
  return m;
}

// The console port: hands the fuzz input to the indicator and checks what comes back.
class FuzzConsole final : public hal::ConsolePort {
 public:
  FuzzConsole(const std::uint8_t* data, std::size_t size, bool paced) : data_(data), size_(size), paced_(paced) {}

  bool exhausted() const { return position_ == size_; }
  void set_indicator_busy(bool busy) { indicator_busy_ = busy; }
  void set_echo(bool echo) { echo_ = echo; }
  void set_jiffy(std::uint32_t jiffy) { jiffy_ = jiffy; }
  std::size_t command_lines() const { return command_lines_; }
  std::size_t answers() const { return answers_; }
  bool may_open() const { return may_open_; }
  bool result_this_jiffy() const { return result_this_jiffy_; }
  // A fault or a dose's end closed the valve: only a line received from now on may open it again.
  // Lines still queued may execute later, so with any unanswered the permission stays.
  void valve_closed_for_good() {
    if (answers_ == command_lines_) may_open_ = false;
  }

  std::size_t read(char* destination, std::size_t capacity) override {
    if (paced_ && indicator_busy_) return 0;  // stdio: the next line once the last one is done
    std::size_t n = 0;
    const std::size_t limit = capacity < kSerialBytesPerJiffy ? capacity : kSerialBytesPerJiffy;
    while (n < limit && position_ < size_) {
      const char c = char(data_[position_++]);
      destination[n++] = c;
      observe_sent(c);
      if (paced_ && (c == '\r' || c == '\n')) break;
    }
    return n;
  }

  void write(const char* data, std::size_t length) override {
    written_this_jiffy_ += length;
    if (written_this_jiffy_ > firmware::TextWriter::kCapacity) violated("a jiffy sent more than the ring holds", jiffy_);
    sent_this_jiffy_.append(data, length);
  }
  void start_jiffy() {
    written_this_jiffy_ = 0;
    sent_this_jiffy_.clear();
    result_this_jiffy_ = false;
  }
  // A jiffy's text is the echo of what it received with whole answer lines at line starts: before
  // it, those its last save released; within it, `ERR 3 busy` right after the echo of a line the
  // queue had no room for; after it, those of this jiffy's commands. An answer may begin like the
  // echo (a released `OK` and a typed `O`), so the split is searched, not guessed.
  void end_jiffy() {
    echo_byte_.assign(sent_this_jiffy_.size(), false);
    no_split_.assign((sent_this_jiffy_.size() + 1) * (echo_expected_.size() + 1), false);
    if (!split(0, 0)) violated("the echo differs from what was typed", jiffy_);
    for (std::size_t i = 0; i < sent_this_jiffy_.size(); ++i) {
      if (!echo_byte_[i]) observe_answer(sent_this_jiffy_[i]);
    }
    echo_expected_.clear();
  }

 private:
  // Whether the text from `sent` on holds the echo from `echoed` on, answer lines only at line
  // starts; marks the echo's bytes on the way back.
  bool split(std::size_t sent, std::size_t echoed) {
    const std::string& text = sent_this_jiffy_;
    if (echoed == echo_expected_.size()) return true;
    if (sent == text.size()) return false;
    const std::size_t state = sent * (echo_expected_.size() + 1) + echoed;
    if (no_split_[state]) return false;
    if (text[sent] == echo_expected_[echoed] && split(sent + 1, echoed + 1)) {
      echo_byte_[sent] = true;
      return true;
    }
    const bool line_start = sent == 0 || text[sent - 1] == '\n';
    const bool answer = text.compare(sent, 2, "OK") == 0 || text.compare(sent, 3, "ERR") == 0;
    const std::size_t line_end = text.find('\n', sent);
    if (line_start && answer && line_end != std::string::npos && split(line_end + 1, echoed)) return true;
    no_split_[state] = true;
    return false;
  }

  // The same line rules the firmware applies (docs/console.md), to know which lines are commands.
  void observe_sent(char c) {
    const firmware::ConsoleLineReader::Event event = mirror_.feed(c);
    if (echo_) echo_expected_ += mirror_.echo();
    switch (event) {
      case firmware::ConsoleLineReader::Event::none:
        return;
      case firmware::ConsoleLineReader::Event::too_long:
        ++command_lines_;  // answered `ERR 2 line too long`
        return;
      case firmware::ConsoleLineReader::Event::line: {
        const LineMeaning m = meaning_of(mirror_.line());
        if (m.command) ++command_lines_;
        if (m.can_open) may_open_ = true;
        return;
      }
    }
  }

  void observe_answer(char c) {
    if (c != '\n' && (c < 0x20 || c > 0x7e)) violated("a non-printable byte in the answers", jiffy_);
    if (c != '\n') {
      if (++answer_length_ > kMaxAnswerLine) violated("an answer line longer than any answer", jiffy_);
      if (answer_length_ <= sizeof answer_start_) answer_start_[answer_length_ - 1] = c;
      return;
    }
    const bool ok = answer_length_ == 2 && std::memcmp(answer_start_, "OK", 2) == 0;
    const bool err = answer_length_ >= 3 && std::memcmp(answer_start_, "ERR", 3) == 0;
    if (answer_length_ >= 6 && std::memcmp(answer_start_, "RESULT", 6) == 0) result_this_jiffy_ = true;
    if (ok || err) {
      if (++answers_ > command_lines_) violated("more answers than command lines", jiffy_);
    }
    answer_length_ = 0;
  }

  const std::uint8_t* data_;
  std::size_t size_;
  bool paced_;
  std::size_t position_ = 0;
  bool indicator_busy_ = false;
  bool echo_ = false;
  std::string echo_expected_;     // the echo of this jiffy's received bytes
  std::string sent_this_jiffy_;  // everything the indicator wrote in this jiffy
  std::vector<bool> echo_byte_;  // which of its bytes are the echo
  std::vector<bool> no_split_;   // (text, echo) positions known not to split
  std::uint32_t jiffy_ = 0;
  firmware::ConsoleLineReader mirror_;
  std::size_t command_lines_ = 0;
  bool may_open_ = false;
  bool result_this_jiffy_ = false;
  std::size_t answers_ = 0;
  std::size_t answer_length_ = 0;
  char answer_start_[6] = {};
  std::size_t written_this_jiffy_ = 0;
};

// Settings persist into a two-slot memory, as on a board: the save path runs too.
class MemoryNvm final : public firmware::NvmBlock {
 public:
  std::size_t size() const override { return sizeof bytes_; }
  bool read(std::size_t offset, std::uint8_t* data, std::size_t length) const override {
    if (offset + length > sizeof bytes_) return false;
    std::memcpy(data, bytes_ + offset, length);
    return true;
  }
  bool write(std::size_t offset, const std::uint8_t* data, std::size_t length) override {
    if (offset + length > sizeof bytes_) return false;
    std::memcpy(bytes_ + offset, data, length);
    return true;
  }

 private:
  std::uint8_t bytes_[firmware::kSettingsSlotsBytes] = {};
};

class SlotStore final : public hal::SettingsStore {
 public:
  bool load(firmware::PersistentSettings& settings) override { return slots_.load(settings); }
  bool save(const firmware::PersistentSettings& settings) override {
    if (!slots_.save(settings)) std::abort();  // a memory that cannot fail must take every save
    return true;
  }

 private:
  MemoryNvm nvm_;
  firmware::SettingsSlots slots_{nvm_};
};

firmware::PersistentSettings calibrated_to_the_toy_plant() {
  firmware::PersistentSettings settings;
  settings.calibration.zero_counts = std::int32_t(fuzz::ToyPlant::kEmptyCounts);
  settings.calibration.counts_per_gram = fuzz::ToyPlant::kCountsPerGram;
  settings.calibration.zero_set = true;
  settings.calibration.span_set = true;
  return settings;
}

void play(const std::uint8_t* data, std::size_t size, bool paced) {
  const auto indicator = std::make_unique<firmware::Indicator>(calibrated_to_the_toy_plant());

  fuzz::ToyPlant plant;
  FuzzConsole console(data, size, paced);
  SlotStore store;
  hal::Ports ports{plant, plant, console, &store};
  bool busy = false;
  for (std::uint32_t jiffy = 0; jiffy < kMaxJiffies; ++jiffy) {
    if (console.exhausted() && !busy) {
      if (console.answers() != console.command_lines()) violated("a command line was never answered", jiffy);
      return;
    }
    console.set_jiffy(jiffy);
    console.set_indicator_busy(busy);
    console.set_echo(indicator->settings().parameters.get(firmware::ParameterId::echo) != 0.0f);
    console.start_jiffy();
    const firmware::Outputs out = hal::run_one_jiffy(*indicator, ports, jiffy).outputs;
    console.end_jiffy();
    busy = out.busy;
    if (console.result_this_jiffy()) console.valve_closed_for_good();
    if (indicator->fault() != firmware::Fault::none) {
      console.valve_closed_for_good();
      if (out.valve != firmware::ValveCommand::closed) violated("valve not closed during a fault", jiffy);
      if (out.state != firmware::IndicatorState::fault) violated("a fault the status frame does not show", jiffy);
    }
    if (out.valve != firmware::ValveCommand::closed && !console.may_open()) {
      violated("valve commanded open without a command that opens it", jiffy);
    }
    if (out.valve_delay_100us > 99) violated("valve delay beyond 99", jiffy);
    plant.advance();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  play(data, size, false);
  play(data, size, true);
  return 0;
}
