#include "dynweigh/modbus/register_map.hpp"

#include <cstdio>

namespace dynweigh::modbus {
namespace {

constexpr std::uint16_t kMaxReadCount = 125;   // the Modbus limit of a read's reply
constexpr std::uint16_t kMaxWriteCount = 123;  // the Modbus limit of a 0x10 request
constexpr const char* kStrategyNames[] = {"model", "preact", "twostage", "learn"};
constexpr std::uint16_t kStrategies = 4;
// The indicator's material table (`material <n>`); X(1) is the only class the PLC can ask for
// until the indicator takes a class (0: the material's, which is X(1) too).
constexpr std::uint16_t kMaterials = 16;

std::uint16_t word_at(const std::uint8_t* bytes) { return std::uint16_t((bytes[0] << 8) | bytes[1]); }

RegisterMap::Outcome refused(Exception exception) {
  RegisterMap::Outcome outcome;
  outcome.exception = exception;
  return outcome;
}

}  // namespace

bool RegisterMap::value_allowed(std::uint16_t address, std::uint16_t value) {
  switch (address) {
    case holding::strategy: return value < kStrategies;
    case holding::material: return value < kMaterials;
    case holding::class_x10: return value == 0 || value == 10;
    case holding::command: return value >= std::uint16_t(PlcCommand::dose) && value <= std::uint16_t(PlcCommand::topup);
    default: return true;  // the target: the console checks it against the scale when the dose starts
  }
}

std::uint16_t RegisterMap::holding_register(std::uint16_t address, const LoopSnapshot& loop) const {
  switch (address) {
    case holding::target_high: return high_word(target_g_);
    case holding::target_low: return low_word(target_g_);
    case holding::strategy: return strategy_;
    case holding::material: return material_written_ ? material_ : loop.selected_material;
    case holding::class_x10: return class_x10_;
    case holding::command: return command_running(loop) ? kCommandRunning : loop.answer_code;
    default: return 0;
  }
}

RegisterMap::Outcome RegisterMap::handle(const std::uint8_t* pdu, std::size_t length, const LoopSnapshot& loop,
                                         std::uint16_t* registers, std::size_t* register_count) {
  *register_count = 0;
  if (length < 1) return refused(Exception::illegal_function);
  const std::uint8_t function = pdu[0];
  switch (function) {
    case kReadHoldingRegisters:
    case kReadInputRegisters:
      if (length != 5) return refused(Exception::illegal_data_value);
      return read(word_at(pdu + 1), word_at(pdu + 3), function == kReadHoldingRegisters, loop, registers,
                  register_count);
    case kWriteSingleRegister:
      if (length != 5) return refused(Exception::illegal_data_value);
      return write(word_at(pdu + 1), 1, pdu + 3, loop);
    case kWriteMultipleRegisters: {
      if (length < 6) return refused(Exception::illegal_data_value);
      const std::uint16_t count = word_at(pdu + 3);
      const std::size_t bytes = pdu[5];
      if (count < 1 || count > kMaxWriteCount || bytes != 2u * count || length != 6 + bytes) {
        return refused(Exception::illegal_data_value);
      }
      return write(word_at(pdu + 1), count, pdu + 6, loop);
    }
    default:
      return refused(Exception::illegal_function);
  }
}

RegisterMap::Outcome RegisterMap::read(std::uint16_t address, std::uint16_t count, bool holding_registers,
                                       const LoopSnapshot& loop, std::uint16_t* registers,
                                       std::size_t* register_count) const {
  if (count < 1 || count > kMaxReadCount) return refused(Exception::illegal_data_value);
  const std::uint32_t end = std::uint32_t(address) + count;
  if (end > (holding_registers ? holding::count : input::count)) return refused(Exception::illegal_data_address);
  for (std::uint16_t i = 0; i < count; ++i) {
    const std::uint16_t at = std::uint16_t(address + i);
    registers[i] = holding_registers ? holding_register(at, loop) : loop.input[at];
  }
  *register_count = count;
  return Outcome{};
}

RegisterMap::Outcome RegisterMap::write(std::uint16_t address, std::uint16_t count, const std::uint8_t* values,
                                        const LoopSnapshot& loop) {
  if (std::uint32_t(address) + count > holding::count) return refused(Exception::illegal_data_address);
  const auto covers = [&](std::uint16_t at) { return at >= address && at < address + count; };
  const auto value = [&](std::uint16_t at) { return word_at(values + 2 * (at - address)); };
  for (std::uint16_t at = address; at < address + count; ++at) {
    if (!value_allowed(at, value(at))) return refused(Exception::illegal_data_value);
  }
  const bool command = covers(holding::command);
  if (command && command_running(loop) && value(holding::command) != std::uint16_t(PlcCommand::abort)) {
    return refused(Exception::server_busy);
  }
  // The set point takes effect with its low word: alone (the high word written before it, or 0),
  // or together with the high word in one 0x10 request.
  if (covers(holding::target_high)) staged_target_high_ = value(holding::target_high);
  if (covers(holding::target_low)) {
    target_g_ = (std::uint32_t(staged_target_high_) << 16) | value(holding::target_low);
  }
  if (covers(holding::strategy)) strategy_ = value(holding::strategy);
  if (covers(holding::material)) {
    material_ = value(holding::material);
    material_written_ = true;
  }
  if (covers(holding::class_x10)) class_x10_ = value(holding::class_x10);
  Outcome outcome;
  if (command) {
    ++issued_sequence_;
    outcome.command_written = true;
    outcome.command = command_request(PlcCommand(value(holding::command)), loop);
    if (outcome.command.command == PlcCommand::dose) material_written_ = false;
  }
  return outcome;
}

CommandRequest RegisterMap::command_request(PlcCommand command, const LoopSnapshot& loop) const {
  CommandRequest request;
  request.sequence = issued_sequence_;
  request.command = command;
  const char* word = "";
  switch (command) {
    case PlcCommand::dose: {
      // A material the PLC wrote is selected as the console's `material <n>` selects it (defining
      // it if it is not yet), on the line before the dose; the one already selected is left alone,
      // so that a dose does not rewrite the settings.
      char select[16] = "";
      if (material_written_ && material_ != loop.selected_material) {
        std::snprintf(select, sizeof select, "material %u\n", unsigned(material_));
      }
      std::snprintf(request.line, sizeof request.line, "%sdose %lu %s", select, static_cast<unsigned long>(target_g_),
                    kStrategyNames[strategy_ < kStrategies ? strategy_ : 0]);
      return request;
    }
    case PlcCommand::abort: word = "abort"; break;
    case PlcCommand::tare: word = "tare"; break;
    case PlcCommand::zero: word = "zero"; break;
    case PlcCommand::clearfault: word = "clearfault"; break;
    case PlcCommand::discharge: word = "discharge"; break;
    case PlcCommand::accept: word = "accept"; break;
    case PlcCommand::topup: word = "topup"; break;
  }
  std::snprintf(request.line, sizeof request.line, "%s", word);
  return request;
}

}  // namespace dynweigh::modbus
