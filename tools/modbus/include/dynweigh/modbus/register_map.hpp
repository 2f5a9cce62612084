#pragma once
// The PLC's view of the indicator (the register map in docs/plc-modbus.md), as a pure function
// of a request's PDU: which registers exist, which values they take, how a 32-bit set point is
// written, and which console command a write to the command register stands for. No sockets, no
// threads, no libmodbus: the servers hand it the PDU libmodbus framed, and the fuzzer hands it
// anything at all.
#include <cstddef>
#include <cstdint>

namespace dynweigh::modbus {

inline constexpr std::uint8_t kReadHoldingRegisters = 0x03;
inline constexpr std::uint8_t kReadInputRegisters = 0x04;
inline constexpr std::uint8_t kWriteSingleRegister = 0x06;
inline constexpr std::uint8_t kWriteMultipleRegisters = 0x10;

enum class Exception : std::uint8_t {
  none = 0,
  illegal_function = 1,
  illegal_data_address = 2,
  illegal_data_value = 3,
  server_busy = 6,  // a command written while the PLC's last one still runs (abort excepted)
};

namespace holding {
inline constexpr std::uint16_t target_high = 0, target_low = 1, strategy = 2, material = 3, class_x10 = 4,
                               command = 5, count = 6;
}
namespace input {
inline constexpr std::uint16_t net_dg = 0, state = 2, fault = 3, valve = 4, result_seq = 5, result_final_dg = 6,
                               result_error_dg = 8, result_time_ms = 10, result_tolerance = 12, result_topups = 13,
                               in_flight_dg = 14, flow_dg_s = 16, count = 18;
}

enum class PlcCommand : std::uint16_t {
  dose = 1, abort = 2, tare = 3, zero = 4, clearfault = 5, discharge = 6, accept = 7, topup = 8
};
inline constexpr std::uint16_t kCommandRunning = 0xFFFF;  // register 5 while the last command runs
inline constexpr std::size_t kCommandLineMax = 48;  // room for `material 15` and a dose, two lines

// What the control loop last published: the input registers and the answer to the PLC's commands.
struct LoopSnapshot {
  std::uint16_t input[input::count] = {};
  std::uint16_t answered_sequence = 0;  // the last PLC command the console path has answered
  std::uint16_t answer_code = 0;        // its answer: 0 OK, else the console's ERR code
  std::uint16_t selected_material = 0;  // the material the indicator has selected (0..15)
};

// A command the PLC wrote, as the console line it stands for.
struct CommandRequest {
  std::uint16_t sequence = 0;
  PlcCommand command = PlcCommand::dose;
  char line[kCommandLineMax] = {};
};

// A 32-bit value in two registers, high word first.
inline std::uint16_t high_word(std::uint32_t value) { return std::uint16_t(value >> 16); }
inline std::uint16_t low_word(std::uint32_t value) { return std::uint16_t(value & 0xFFFFu); }

class RegisterMap {
 public:
  struct Outcome {
    Exception exception = Exception::none;
    bool command_written = false;  // `command` holds a new command for the console path
    CommandRequest command;
  };

  // One request PDU (function code first, no unit id, no checksum) against the loop's snapshot.
  // A write applies whole or not at all. On a read, `registers` (room for 125) gets the values.
  Outcome handle(const std::uint8_t* pdu, std::size_t length, const LoopSnapshot& loop, std::uint16_t* registers,
                 std::size_t* register_count);

  // The holding registers as a read shows them now.
  std::uint16_t holding_register(std::uint16_t address, const LoopSnapshot& loop) const;
  std::uint32_t target_g() const { return target_g_; }
  std::uint16_t issued_sequence() const { return issued_sequence_; }

 private:
  Outcome read(std::uint16_t address, std::uint16_t count, bool holding_registers, const LoopSnapshot& loop,
               std::uint16_t* registers, std::size_t* register_count) const;
  Outcome write(std::uint16_t address, std::uint16_t count, const std::uint8_t* values, const LoopSnapshot& loop);
  static bool value_allowed(std::uint16_t address, std::uint16_t value);
  bool command_running(const LoopSnapshot& loop) const { return issued_sequence_ != loop.answered_sequence; }
  CommandRequest command_request(PlcCommand command, const LoopSnapshot& loop) const;

  std::uint32_t target_g_ = 0;
  std::uint16_t staged_target_high_ = 0;  // a high word written alone waits for its low word
  std::uint16_t strategy_ = 0;
  std::uint16_t material_ = 0;
  bool material_written_ = false;  // the PLC's next dose selects `material_` first
  std::uint16_t class_x10_ = 0;
  std::uint16_t issued_sequence_ = 0;
};

}  // namespace dynweigh::modbus
