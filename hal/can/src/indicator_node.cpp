#include "dynweigh/hal/can/indicator_node.hpp"

#include "dynweigh/hal/can/protocol.hpp"

namespace dynweigh::hal::can {
namespace {

// The ingredient valve (1..7) a standard frame with this id and `base` (0x220 or 0x1A0) is for, or 0.
std::uint8_t ingredient_of(const CanFrame& frame, std::uint32_t base) {
  if (frame.extended || frame.remote || frame.id <= base || frame.id >= base + CanIngredientValves::kValves) return 0;
  return std::uint8_t(frame.id - base);
}

// Our own frames, echoed by a bus, prove nothing about the plant's side of it.
bool from_the_plant(const CanFrame& frame) {
  if (ingredient_of(frame, kIdValveCommand) != 0) return false;
  switch (classify(frame)) {
    case MessageKind::valve_command:
    case MessageKind::gate_command:
    case MessageKind::indicator_status:
      return false;
    case MessageKind::heartbeat:
      return frame.id != kIdHeartbeatBase + kNodeIndicator;
    default:
      return true;
  }
}

}  // namespace

IndicatorNode::IndicatorNode(firmware::Indicator& indicator, ConsolePort& console, CanLink& link,
                             const IndicatorNodeOptions& options)
    : indicator_(indicator),
      link_(link),
      heartbeat_jiffies_(options.heartbeat_jiffies),
      ports_{load_cell_, valve_, console, options.settings, firmware::SettingsSave::none, options.probe, nullptr, &gate_, &ingredients_} {}

IndicatorNode::Heard IndicatorNode::receive(const CanFrame& frame) {
  if (from_the_plant(frame)) heard_since_jiffy_ = plant_heard_ = true;
  switch (classify(frame)) {
    case MessageKind::load_cell_sample:
      return on_sample(frame);
    case MessageKind::valve_feedback: {
      ValveFeedbackMessage m;
      if (!decode(frame, m)) return Heard::ignored;
      valve_.deliver_position(firmware::ValvePosition{m.position});
      return Heard::valve_position;
    }
    case MessageKind::gate_feedback: {
      GateFeedbackMessage m;
      if (!decode(frame, m)) return Heard::ignored;
      gate_.deliver_position(firmware::GatePosition{m.position});
      gate_.deliver_faults(m.faults);
      return Heard::gate_position;
    }
    case MessageKind::heartbeat: {
      HeartbeatMessage m;
      if (!decode(frame, m) || m.node != kNodeLoadCell || m.nmt_state != kNmtStopped) return Heard::ignored;
      sequence_.reset();  // a plant that comes back counts afresh
      return Heard::plant_stopped;
    }
    default: {
      // An ingredient valve's feedback: the 0x1A0 payload under its own id.
      const std::uint8_t ingredient = ingredient_of(frame, kIdValveFeedback);
      if (ingredient == 0) return Heard::ignored;
      CanFrame as_valve = frame;
      as_valve.id = kIdValveFeedback;
      ValveFeedbackMessage m;
      if (!decode(as_valve, m)) return Heard::ignored;
      ingredients_.deliver_position(ingredient, firmware::ValvePosition{m.position});
      return Heard::ingredient_position;
    }
  }
}

IndicatorNode::Heard IndicatorNode::on_sample(const CanFrame& frame) {
  LoadCellSampleMessage m;
  if (!decode(frame, m)) return Heard::ignored;
  const SampleSequence::Arrival arrival = sequence_.arrive(m.counter);
  if (!arrival.accept) return Heard::repeated_sample;  // the indicator has it already, or is past it
  for (std::uint16_t i = 0; i < arrival.missing; ++i) run_jiffy(link_status(true), /*answer=*/false);
  load_cell_.deliver(firmware::LoadCellInput{m.raw_counts, m.counter, m.status, true, firmware::LinkStatus::ok});
  run_jiffy(link_status(true), /*answer=*/true);
  return Heard::sample;
}

void IndicatorNode::run_without_sample() {
  run_jiffy(link_status(heard_since_jiffy_), /*answer=*/true);
  sequence_.stood_in();
}

firmware::LinkStatus IndicatorNode::link_status(bool heard) const {
  if (link_.bus_off()) return firmware::LinkStatus::bus_off;
  return heard ? firmware::LinkStatus::ok : firmware::LinkStatus::silent;
}

void IndicatorNode::run_jiffy(firmware::LinkStatus link, bool answer) {
  load_cell_.set_link(link);
  heard_since_jiffy_ = false;
  record_ = run_one_jiffy(indicator_, ports_, jiffy_);
  const firmware::Outputs& outputs = record_.outputs;
  if (answer) {
    // The gate's command before the 0x220 that closes the jiffy for the plant.
    if (gate_.commanded()) {
      link_.send(encode(GateCommandMessage{std::uint8_t(gate_.last_command()), outputs.answered_counter}));
    }
    send_ingredient_commands(outputs.answered_counter);
    // Exactly one 0x220 per sample: the lockstep acknowledgement and the valve module's watchdog.
    link_.send(encode(ValveCommandMessage{std::uint8_t(valve_.last_command()), valve_.last_delay_100us(),
                                          outputs.answered_counter}));
    link_.send(encode(IndicatorStatusMessage{outputs.weight_100mg, std::uint8_t(outputs.state),
                                             std::uint8_t(outputs.valve), outputs.answered_counter}));
  }
  ++jiffy_;
  if (heartbeat_jiffies_ != 0 && jiffy_ % heartbeat_jiffies_ == 0) send_heartbeat(kNmtOperational);
}

// The ingredient valves' commands, before the 0x220 that closes the jiffy for the plant.
void IndicatorNode::send_ingredient_commands(std::uint16_t counter) {
  for (std::uint8_t i = 1; i < CanIngredientValves::kValves; ++i) {
    if ((ingredients_.commanded() & (1u << i)) == 0) continue;
    CanFrame frame = encode(ValveCommandMessage{std::uint8_t(ingredients_.command_of(i)), ingredients_.delay_of(i), counter});
    frame.id = kIdValveCommand + i;
    link_.send(frame);
  }
}

void IndicatorNode::send_heartbeat(std::uint8_t nmt_state) {
  link_.send(encode(HeartbeatMessage{kNodeIndicator, nmt_state}));
}

void IndicatorNode::leave() {
  if (valve_.last_command() != firmware::ValveCommand::closed) {
    valve_.command(firmware::ValveCommand::closed, 0);
    link_.send(encode(ValveCommandMessage{std::uint8_t(firmware::ValveCommand::closed), 0, record_.outputs.answered_counter}));
  }
  if (ingredients_.commanded() != 0) {
    ingredients_.close_all();
    send_ingredient_commands(record_.outputs.answered_counter);
  }
  if (gate_.last_command() != firmware::GateCommand::closed) {
    gate_.command(firmware::GateCommand::closed);
    link_.send(encode(GateCommandMessage{std::uint8_t(firmware::GateCommand::closed), record_.outputs.answered_counter}));
  }
  send_heartbeat(kNmtStopped);
}

}  // namespace dynweigh::hal::can
