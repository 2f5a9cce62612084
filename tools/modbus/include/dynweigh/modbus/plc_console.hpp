#pragma once
// The PLC's commands on the console's own command path. This port sits between the board and the
// operator's console: it hands the indicator the console line a PLC command stands for (`dose 5000
// model`, `tare`, ...), reads the indicator's answers to tell the PLC its OK or ERR code, and
// publishes the indicator's state to the Modbus servers once a jiffy, without waiting for them.
//
// One side's command at a time: while a PLC command runs, the operator's next line waits; while
// an operator's command runs, the PLC's waits (register 5 reads 0xFFFF) - except an abort, which
// goes in at once from either side. Every answer still reaches the operator's console.
#include <cstddef>
#include <cstdint>

#include "dynweigh/firmware/console_line_reader.hpp"
#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/hal/ports.hpp"
#include "dynweigh/modbus/plc_mailbox.hpp"
#include "dynweigh/modbus/result_fields.hpp"

namespace dynweigh::modbus {

class PlcConsole final : public hal::ConsolePort {
 public:
  PlcConsole(hal::ConsolePort& operator_console, PlcMailbox& mailbox);

  std::size_t read(char* destination, std::size_t capacity) override;
  void write(const char* data, std::size_t length) override;
  // While a PLC command runs its answer must come through even when nobody reads the console.
  std::size_t writable() const override;

  // Before every jiffy: the PLC's next command, if the console path can take it now (it goes to
  // the indicator in this jiffy).
  void before_jiffy() { exchange(); }
  // After every jiffy: the registers from the indicator's outputs, published; the watchdog (param
  // plc_watchdog_ms) over a PLC's dose.
  void after_jiffy(const firmware::Indicator& indicator, const firmware::Outputs& outputs);
  // A PLC command waits for the console path (a loop that idles may not).
  bool command_waiting() { return inject_ || mailbox_.command_waiting(); }

  bool watchdog_fired() const { return watchdog_fired_; }
  std::uint32_t requests() const { return requests_; }

 private:
  enum class Origin : std::uint8_t { operator_console, plc, watchdog };
  struct Awaited {
    Origin origin;
    std::uint16_t sequence;
    bool dose;
    bool prelude;  // a line before the PLC command's own (`material <n>` before a dose)
  };
  static constexpr std::size_t kAwaited = 16;

  void await(Origin origin, std::uint16_t sequence, bool dose, bool prelude = false);
  bool awaits(Origin origin) const;
  bool plc_dose_running() const;
  void track_operator_bytes(const char* data, std::size_t length);
  void answer_line(const char* line);
  void fill_registers(const firmware::Indicator& indicator, const firmware::Outputs& outputs);
  void watch(const firmware::Indicator& indicator);
  void exchange();

  hal::ConsolePort& operator_;
  PlcMailbox& mailbox_;
  firmware::ConsoleLineReader operator_lines_;  // a shadow of the indicator's reader: which lines it answers
  std::size_t operator_typed_ = 0;              // characters of an unfinished operator line

  Awaited awaited_[kAwaited] = {};
  std::size_t awaited_head_ = 0, awaited_count_ = 0;

  bool inject_ = false;  // `inject_line_` goes to the indicator in the next read()
  char inject_line_[kCommandLineMax + 1] = {};
  Origin inject_origin_ = Origin::plc;
  CommandRequest inject_command_;

  char answer_[firmware::ConsoleLineReader::kMaxLine * 3] = {};
  std::size_t answer_length_ = 0;

  LoopSnapshot snapshot_;
  ResultFields result_;
  std::uint16_t result_seq_ = 0;
  std::uint16_t prelude_error_ = 0;  // a prelude's ERR code: the PLC command answers it, not its own OK
  std::int32_t dose_start_100mg_ = 0;
  bool was_dosing_ = false;
  static constexpr std::size_t kFlowWindow = 10;  // jiffies the flow is measured over
  std::int32_t weights_[kFlowWindow + 1] = {};
  std::size_t weights_seen_ = 0;

  std::uint32_t requests_ = 0;
  std::uint32_t jiffies_without_request_ = 0;
  bool watchdog_fired_ = false;
};

}  // namespace dynweigh::modbus
