// Fuzz target: arbitrary bytes as a PLC's stream of Modbus request PDUs against the register map
// (the project's own decoding; libmodbus only frames them), with the control loop answering
// commands in between, and as console lines for the RESULT field reader.
//
// Input: records of <length byte><PDU bytes>; a length byte of 0xFF is the loop answering the last
// command with the next byte as its code. The rest, after the last whole record, is a RESULT line.
//
// Invariants: every answer is a reply or one of the exceptions 01, 02, 03, 06; a read returns as
// many registers as asked (1..125) and register 5 reads 0xFFFF exactly while a command runs; a
// refused write changes no register; a command's console line is one of the command words (a
// dose names the set point the registers hold and a strategy); a written set point pair reads
// back as written.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "dynweigh/modbus/register_map.hpp"
#include "dynweigh/modbus/result_fields.hpp"

namespace {

using namespace dynweigh::modbus;

[[noreturn]] void violated(const char* what) {
  std::fprintf(stderr, "Modbus register map invariant violated: %s\n", what);
  std::abort();
}

struct Holding {
  std::uint16_t r[holding::count];
  bool operator==(const Holding& o) const { return std::memcmp(r, o.r, sizeof r) == 0; }
};

Holding holding_of(const RegisterMap& map, const LoopSnapshot& loop) {
  Holding h{};
  for (std::uint16_t a = 0; a < holding::count; ++a) h.r[a] = map.holding_register(a, loop);
  return h;
}

void check_command_line(const CommandRequest& c, const RegisterMap& map) {
  if (std::memchr(c.line, '\0', sizeof c.line) == nullptr) violated("command line not terminated");
  std::string line = c.line;
  if (c.command == PlcCommand::dose) {
    // A material the PLC wrote is selected on a line of its own before the dose.
    if (line.rfind("material ", 0) == 0) {
      const std::size_t end = line.find('\n');
      if (end == std::string::npos) violated("material line without the dose after it");
      const std::string number = line.substr(9, end - 9);
      if (number.empty() || number.size() > 2 || number.find_first_not_of("0123456789") != std::string::npos ||
          std::stoi(number) > 15) {
        violated("material line names no material 0..15");
      }
      line = line.substr(end + 1);
    }
    const std::string expected = "dose " + std::to_string(map.target_g()) + " ";
    if (line.rfind(expected, 0) != 0) violated("dose line does not carry the set point");
    const std::string strategy = line.substr(expected.size());
    if (strategy != "model" && strategy != "preact" && strategy != "twostage" && strategy != "learn") {
      violated("dose line names no strategy");
    }
    return;
  }
  static const char* const kWords[] = {"abort", "tare", "zero", "clearfault", "discharge", "accept", "topup"};
  for (const char* w : kWords) {
    if (line == w) return;
  }
  violated("command line is no command word");
}

void check_reply(const std::uint8_t* pdu, std::size_t length, const RegisterMap::Outcome& outcome,
                 std::size_t count, const RegisterMap& map, const LoopSnapshot& loop, const Holding& before) {
  switch (outcome.exception) {
    case Exception::none:
    case Exception::illegal_function:
    case Exception::illegal_data_address:
    case Exception::illegal_data_value:
    case Exception::server_busy:
      break;
    default:
      violated("an exception code outside 01, 02, 03, 06");
  }
  const Holding after = holding_of(map, loop);
  const bool running = map.issued_sequence() != loop.answered_sequence;
  if ((after.r[holding::command] == kCommandRunning) != running) violated("register 5 and the command disagree");
  if (outcome.exception != Exception::none) {
    if (!(after == before)) violated("a refused request changed a register");
    if (outcome.command_written || count != 0) violated("a refused request wrote a command or read registers");
    return;
  }
  const std::uint8_t function = pdu[0];
  if (function == kReadHoldingRegisters || function == kReadInputRegisters) {
    const std::size_t asked = std::size_t((pdu[3] << 8) | pdu[4]);
    if (count != asked || count < 1 || count > 125) violated("a read returned another count than asked");
  } else if (count != 0) {
    violated("a write returned registers");
  }
  if (function == kWriteMultipleRegisters && length >= 6) {
    const std::uint16_t address = std::uint16_t((pdu[1] << 8) | pdu[2]);
    const std::uint16_t n = std::uint16_t((pdu[3] << 8) | pdu[4]);
    if (address == 0 && n >= 2) {
      const std::uint32_t written = (std::uint32_t((pdu[6] << 8) | pdu[7]) << 16) | std::uint32_t((pdu[8] << 8) | pdu[9]);
      if (map.target_g() != written) violated("a set point written whole reads back otherwise");
    }
  }
  if (outcome.command_written) check_command_line(outcome.command, map);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  RegisterMap map;
  LoopSnapshot loop;
  for (std::uint16_t i = 0; i < input::count; ++i) loop.input[i] = std::uint16_t(i * 0x1111u);
  std::uint16_t registers[125];
  std::size_t at = 0;
  while (at < size) {
    const std::size_t length = data[at];
    if (length == 0xFF) {
      if (at + 1 >= size) break;
      loop.answered_sequence = map.issued_sequence();
      loop.answer_code = data[at + 1];
      at += 2;
      continue;
    }
    if (at + 1 + length > size) break;
    const std::uint8_t* pdu = data + at + 1;
    const Holding before = holding_of(map, loop);
    std::size_t count = 0;
    const RegisterMap::Outcome outcome = map.handle(pdu, length, loop, registers, &count);
    check_reply(pdu, length, outcome, count, map, loop, before);
    at += 1 + length;
  }
  const std::string rest(reinterpret_cast<const char*>(data + at), size - at);
  ResultFields fields;
  const bool is_result = parse_result_line(rest.c_str(), fields);
  if (is_result != (rest.compare(0, 7, "RESULT ") == 0)) violated("a RESULT line not taken for one, or the reverse");
  return 0;
}
