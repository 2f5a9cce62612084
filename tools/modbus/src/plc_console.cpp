#include "dynweigh/modbus/plc_console.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>

namespace dynweigh::modbus {
namespace {

void put_int32(std::uint16_t* registers, std::uint16_t at, std::int32_t value) {
  const auto bits = static_cast<std::uint32_t>(value);
  registers[at] = high_word(bits);
  registers[at + 1] = low_word(bits);
}

std::int32_t to_decigrams(float grams) {
  const float dg = grams * 10.0f;
  if (!(std::fabs(dg) < 2.0e9f)) return 0;
  return std::int32_t(std::lround(dg));
}

}  // namespace

PlcConsole::PlcConsole(hal::ConsolePort& operator_console, PlcMailbox& mailbox)
    : operator_(operator_console), mailbox_(mailbox) {}

void PlcConsole::await(Origin origin, std::uint16_t sequence, bool dose, bool prelude) {
  if (awaited_count_ == kAwaited) return;  // more than a console holds in flight: the indicator refuses them anyway
  awaited_[(awaited_head_ + awaited_count_) % kAwaited] = Awaited{origin, sequence, dose, prelude};
  ++awaited_count_;
}

bool PlcConsole::awaits(Origin origin) const {
  for (std::size_t i = 0; i < awaited_count_; ++i) {
    if (awaited_[(awaited_head_ + i) % kAwaited].origin == origin) return true;
  }
  return false;
}

bool PlcConsole::plc_dose_running() const {
  for (std::size_t i = 0; i < awaited_count_; ++i) {
    const Awaited& a = awaited_[(awaited_head_ + i) % kAwaited];
    if (a.origin == Origin::plc && a.dose) return true;
  }
  return false;
}

std::size_t PlcConsole::read(char* destination, std::size_t capacity) {
  if (inject_) {
    const std::size_t n = std::strlen(inject_line_);
    if (n + 1 > capacity) return 0;  // the board's buffer is smaller than a line: the next read takes it
    inject_ = false;
    std::memcpy(destination, inject_line_, n);
    destination[n] = '\n';
    const bool dose = inject_origin_ == Origin::plc && inject_command_.command == PlcCommand::dose;
    for (const char* c = inject_line_; *c != '\0'; ++c) {
      if (*c == '\n') await(inject_origin_, inject_command_.sequence, false, true);
    }
    await(inject_origin_, inject_command_.sequence, dose);
    return n + 1;
  }
  if (awaits(Origin::plc) || awaits(Origin::watchdog)) return 0;  // the operator's line waits in its port
  const std::size_t n = operator_.read(destination, capacity);
  track_operator_bytes(destination, n);
  return n;
}

void PlcConsole::track_operator_bytes(const char* data, std::size_t length) {
  for (std::size_t i = 0; i < length; ++i) {
    const char c = data[i];
    if (operator_lines_.feed(c) != firmware::ConsoleLineReader::Event::none) {
      await(Origin::operator_console, 0, false);
    }
    if (c == '\r' || c == '\n') {
      operator_typed_ = 0;
    } else if (c == '\b' || c == 0x7f) {
      if (operator_typed_ > 0) --operator_typed_;
    } else if (c != '\0') {
      ++operator_typed_;
    }
  }
}

std::size_t PlcConsole::writable() const {
  if (awaits(Origin::plc) || awaits(Origin::watchdog)) return std::numeric_limits<std::size_t>::max();
  return operator_.writable();
}

void PlcConsole::write(const char* data, std::size_t length) {
  for (std::size_t i = 0; i < length; ++i) {
    const char c = data[i];
    if (c == '\n') {
      answer_[answer_length_] = '\0';
      answer_line(answer_);
      answer_length_ = 0;
    } else if (c != '\r' && answer_length_ + 1 < sizeof answer_) {
      answer_[answer_length_++] = c;
    }
  }
  // The operator's console gets what it can take; a PLC's answer does not wait for it.
  const std::size_t room = operator_.writable();
  operator_.write(data, length < room ? length : room);
}

void PlcConsole::answer_line(const char* line) {
  if (parse_result_line(line, result_)) {
    ++result_seq_;
    return;
  }
  const bool ok = std::strcmp(line, "OK") == 0;
  if (!ok && std::strncmp(line, "ERR ", 4) != 0) return;
  if (awaited_count_ == 0) return;
  const Awaited answered = awaited_[awaited_head_];
  awaited_head_ = (awaited_head_ + 1) % kAwaited;
  --awaited_count_;
  if (answered.origin != Origin::plc) return;
  const std::uint16_t code = ok ? 0 : std::uint16_t(std::strtol(line + 4, nullptr, 10));
  if (answered.prelude) {
    if (prelude_error_ == 0) prelude_error_ = code;
    return;
  }
  snapshot_.answered_sequence = answered.sequence;
  snapshot_.answer_code = prelude_error_ != 0 ? prelude_error_ : code;
  prelude_error_ = 0;
}

void PlcConsole::fill_registers(const firmware::Indicator& indicator, const firmware::Outputs& outputs) {
  std::uint16_t* r = snapshot_.input;
  const bool known = outputs.weight_100mg != firmware::kWeightUnknown100mg;
  put_int32(r, input::net_dg, outputs.weight_100mg);
  r[input::state] = std::uint16_t(outputs.state);
  r[input::fault] = std::uint16_t(outputs.fault);
  r[input::valve] = std::uint16_t(outputs.valve);
  r[input::result_seq] = result_seq_;
  put_int32(r, input::result_final_dg, result_.final_g * 10);
  put_int32(r, input::result_error_dg, result_.error_g * 10);
  r[input::result_time_ms] = high_word(result_.time_ms);
  r[input::result_time_ms + 1] = low_word(result_.time_ms);
  r[input::result_tolerance] = result_.tolerance;
  r[input::result_topups] = result_.topups;
  snapshot_.selected_material = std::uint16_t(indicator.settings().materials.selected());

  // In flight: what the strategy predicts the fill will reach, less what has landed of it.
  const bool dosing = outputs.state == firmware::IndicatorState::dosing;
  if (dosing && !was_dosing_) dose_start_100mg_ = known ? outputs.weight_100mg : 0;
  was_dosing_ = dosing;
  std::int32_t in_flight = 0;
  if (dosing && known) {
    const float landed_g = float(outputs.weight_100mg - dose_start_100mg_) / 10.0f;
    const float predicted_g = outputs.predicted_g;
    if (predicted_g > landed_g) in_flight = to_decigrams(predicted_g - landed_g);
  }
  put_int32(r, input::in_flight_dg, in_flight);

  // Flow: the weight's rise over the last kFlowWindow jiffies.
  if (!known) weights_seen_ = 0;
  std::int32_t flow = 0;
  if (known) {
    weights_[weights_seen_ % (kFlowWindow + 1)] = outputs.weight_100mg;
    ++weights_seen_;
    if (weights_seen_ > kFlowWindow) {
      const std::int32_t newest = weights_[(weights_seen_ - 1) % (kFlowWindow + 1)];
      const std::int32_t oldest = weights_[weights_seen_ % (kFlowWindow + 1)];
      const float jiffy_s = indicator.settings().parameters.get(firmware::ParameterId::jiffy_ms) / 1000.0f;
      flow = to_decigrams(float(newest - oldest) / 10.0f / (float(kFlowWindow) * jiffy_s));
    }
  }
  put_int32(r, input::flow_dg_s, flow);
}

void PlcConsole::watch(const firmware::Indicator& indicator) {
  const float limit_ms = indicator.settings().parameters.get(firmware::ParameterId::plc_watchdog_ms);
  if (!plc_dose_running() || limit_ms <= 0.0f) {
    jiffies_without_request_ = 0;
    return;
  }
  ++jiffies_without_request_;
  const float jiffy_ms = indicator.settings().parameters.get(firmware::ParameterId::jiffy_ms);
  if (float(jiffies_without_request_) * jiffy_ms < limit_ms || inject_ || awaits(Origin::watchdog)) return;
  std::fprintf(stderr, "dynweigh-fw: plc watchdog: no Modbus request for %.0f ms during the PLC's dose: abort\n",
               double(limit_ms));
  std::snprintf(inject_line_, sizeof inject_line_, "abort");
  inject_origin_ = Origin::watchdog;
  inject_command_ = CommandRequest{};
  inject_command_.command = PlcCommand::abort;
  inject_ = true;
  watchdog_fired_ = true;
}

void PlcConsole::after_jiffy(const firmware::Indicator& indicator, const firmware::Outputs& outputs) {
  fill_registers(indicator, outputs);
  exchange();
  watch(indicator);
}

void PlcConsole::exchange() {
  const bool between_lines = operator_typed_ == 0 && !inject_;
  PlcMailbox::Exchange exchange;
  if (mailbox_.try_exchange(snapshot_, between_lines && awaited_count_ == 0, between_lines, exchange)) {
    if (exchange.requests != requests_) jiffies_without_request_ = 0;
    requests_ = exchange.requests;
    if (exchange.taken) {
      std::snprintf(inject_line_, sizeof inject_line_, "%s", exchange.command.line);
      inject_origin_ = Origin::plc;
      inject_command_ = exchange.command;
      inject_ = true;
    }
  }
}

}  // namespace dynweigh::modbus
