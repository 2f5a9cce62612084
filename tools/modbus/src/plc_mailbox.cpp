#include "dynweigh/modbus/plc_mailbox.hpp"

namespace dynweigh::modbus {

RegisterMap::Outcome PlcMailbox::serve(const std::uint8_t* pdu, std::size_t length, std::uint16_t* registers,
                                       std::size_t* register_count) {
  const std::lock_guard<std::mutex> lock(mutex_);
  ++requests_;
  const RegisterMap::Outcome outcome = map_.handle(pdu, length, snapshot_, registers, register_count);
  if (outcome.command_written) {
    waiting_ = true;
    waiting_command_ = outcome.command;
  }
  return outcome;
}

bool PlcMailbox::try_exchange(const LoopSnapshot& snapshot, bool take_any, bool take_abort, Exchange& exchange) {
  const std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return false;
  snapshot_ = snapshot;
  exchange.requests = requests_;
  exchange.taken = waiting_ && (take_any || (take_abort && waiting_command_.command == PlcCommand::abort));
  if (exchange.taken) {
    exchange.command = waiting_command_;
    waiting_ = false;
  }
  return true;
}

}  // namespace dynweigh::modbus
