// dynweigh plant: the load-cell module (0x190), the valve module (0x220 in, 0x1A0 out) and the
// discharge gate module (0x228 in, 0x1A8 out) of docs/can-protocol.md played by the simulator or by
// a recording, on any CAN transport; with a scene that has ingredients, their valve modules too
// (ingredient i: 0x220 + i in, 0x1A0 + i out, payloads as 0x220 / 0x1A0).
//
// Lockstep (default): wait until the indicator is heard (any frame of node 1), then for each jiffy
// k: send the valve and gate feedback and sample k, wait for the 0x220 carrying counter k (a 0x228
// before it moves the gate), apply its command with its delay, advance the plant one jiffy. Real time (--realtime): a sample every 10 ms of wall
// time whatever the indicator does; the valve module closes when it has heard no command for 50 ms.
// Ends when the indicator says it stops (heartbeat NMT state 0x04), when the link closes, after
// --jiffies, at the end of a replay, or on SIGINT/SIGTERM; then prints its summary as key=value.
#include <CLI/CLI.hpp>

#include <poll.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dynweigh/hal/can/protocol.hpp"
#include "dynweigh/hal/linux/can_transport.hpp"
#include "dynweigh/sim/plant.hpp"
#include "dynweigh/sim/scene.hpp"
#include "finite_range.hpp"
#include "plant_commands.hpp"
#include "recorded_samples.hpp"
#include "command_line.hpp"

namespace {

using namespace dynweigh;
namespace can = dynweigh::hal::can;
using hal::linux_can::CanFrame;
using hal::linux_can::CanTransport;
using Clock = std::chrono::steady_clock;

constexpr double kJiffyS = 0.010;
constexpr int kWatchdogJiffies = 5;  // docs/can-protocol.md: no command for 50 ms -> close

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

struct Options {
  std::string transport;
  std::string scene = "default";
  std::uint64_t seed = 1;
  bool realtime = false;
  std::string replay;
  std::uint32_t jiffies = 0;
  double wait_s = 30.0;
  double timeout_s = 10.0;
  bool verbose = false;
};

struct Stats {
  std::uint32_t jiffies = 0;
  std::uint32_t answers = 0;
  std::uint32_t late_answers = 0;  // 0x220 with another counter than the one awaited
  std::uint32_t malformed = 0;
  std::uint32_t watchdog_closes = 0;
  std::uint32_t valve_opens = 0;
  std::uint32_t gate_opens = 0;
  std::uint32_t ingredient_commands = 0;          // 0x221..0x227 for an ingredient the scene has
  std::uint32_t ignored_ingredient_commands = 0;  // ... for one it lacks
  long first_open_jiffy = -1;
  long last_close_jiffy = -1;
  std::int32_t indicator_weight_100mg = 0;
  bool indicator_seen = false;
  const char* end = "running";
};

// The valve module and load-cell module around either the physics or a recording.
class Modules {
 public:
  Modules(const Options& options, std::optional<sim::Plant>& plant, const std::vector<std::int32_t>& replay)
      : plant_(plant), replay_(replay) {
    (void)options;
  }

  bool has_sample(std::uint32_t k) const { return plant_.has_value() || k < replay_.size(); }

  can::LoadCellSampleMessage sample(std::uint32_t k) {
    if (plant_) {
      const sim::LoadCellSample s = plant_->sample();
      return {s.raw_counts, s.counter, s.status};
    }
    return {replay_[k], std::uint16_t(k & 0xFFFFu), 0};
  }

  can::ValveFeedbackMessage feedback() const {
    if (plant_) return {static_cast<std::uint8_t>(plant_->valve_feedback()), 0};
    static constexpr std::uint8_t kPositionOf[] = {0, 2, 3};  // a recording's valve follows at once
    return {kPositionOf[static_cast<int>(command_)], 0};
  }

  void command(sim::ValveCommand command, double delay_s, Stats& stats, std::uint32_t jiffy) {
    if (command != command_) {
      if (command != sim::ValveCommand::closed && command_ == sim::ValveCommand::closed) {
        ++stats.valve_opens;
        if (stats.first_open_jiffy < 0) stats.first_open_jiffy = jiffy;
      }
      if (command == sim::ValveCommand::closed) stats.last_close_jiffy = jiffy;
    }
    command_ = command;
    if (plant_) plant_->command_valve(command, delay_s);
  }

  can::GateFeedbackMessage gate_feedback() const {
    if (plant_) return {static_cast<std::uint8_t>(plant_->gate_feedback()), 0};
    return {gate_command_, 0};  // a recording's gate follows at once (2 open -> 3 open)
  }

  void command_gate(std::uint8_t command, Stats& stats) {
    const std::uint8_t position = command == 2 ? 3 : 0;
    if (position == 3 && gate_command_ != 3) ++stats.gate_opens;
    gate_command_ = position;
    if (plant_) plant_->command_gate(command == 2 ? sim::GateCommand::open : sim::GateCommand::closed);
  }

  // Ingredient valves 1.. (ingredient 0 is the valve above); a recording has none.
  std::size_t ingredients() const { return plant_ ? plant_->ingredient_count() : 1; }
  can::ValveFeedbackMessage ingredient_feedback(std::size_t ingredient) const {
    return {static_cast<std::uint8_t>(plant_->ingredient_valve_feedback(ingredient)), 0};
  }
  void command_ingredient(std::size_t ingredient, sim::ValveCommand command, double delay_s, Stats& stats) {
    if (plant_ && plant_->command_ingredient_valve(ingredient, command, delay_s)) {
      ++stats.ingredient_commands;
    } else {
      ++stats.ignored_ingredient_commands;
    }
  }
  void close_ingredients() {
    for (std::size_t i = 1; plant_ && i < plant_->ingredient_count(); ++i) {
      plant_->command_ingredient_valve(i, sim::ValveCommand::closed);
    }
  }

  void advance() {
    if (plant_) plant_->advance(kJiffyS);
  }

 private:
  std::optional<sim::Plant>& plant_;
  const std::vector<std::int32_t>& replay_;
  sim::ValveCommand command_ = sim::ValveCommand::closed;
  std::uint8_t gate_command_ = 0;  // as its feedback: 0 closed, 3 open
};

enum class Heard { nothing, answer, gate, ingredient, other, stopped, closed };

// An ingredient valve's command (0x221..0x227): the 0x220 payload for valve `ingredient`.
struct IngredientCommand {
  std::size_t ingredient = 0;
  can::ValveCommandMessage message;
};

constexpr std::size_t kMaxIngredientNodes = 8;  // nodes 0x20..0x27

std::size_t ingredient_of(std::uint32_t id) {
  const bool in_range = !(id < can::kIdValveCommand + 1 || id >= can::kIdValveCommand + kMaxIngredientNodes);
  return in_range ? std::size_t(id - can::kIdValveCommand) : 0;
}

bool decode_ingredient(const CanFrame& frame, IngredientCommand& out) {
  if (frame.extended) return false;
  out.ingredient = ingredient_of(frame.id);
  if (out.ingredient == 0) return false;
  CanFrame as_valve = frame;  // the same payload as ingredient 0's
  as_valve.id = can::kIdValveCommand;
  return can::decode(as_valve, out.message);
}

CanFrame encode_ingredient_feedback(std::size_t ingredient, const can::ValveFeedbackMessage& message) {
  CanFrame frame = can::encode(message);
  frame.id = can::kIdValveFeedback + std::uint32_t(ingredient);
  return frame;
}

// One frame from the link, sorted; `answer` fills `command`, `gate` fills `gate`, `ingredient`
// fills `ingredient`.
Heard listen(CanTransport& link, int timeout_ms, Stats& stats, can::ValveCommandMessage& command,
             can::GateCommandMessage& gate, IngredientCommand& ingredient, bool verbose) {
  CanFrame frame;
  const int got = link.receive(frame, timeout_ms);
  if (got < 0) return Heard::closed;
  if (got == 0) return Heard::nothing;
  switch (can::classify(frame)) {
    case can::MessageKind::valve_command:
      if (can::decode(frame, command)) {
        stats.indicator_seen = true;
        return Heard::answer;
      }
      break;
    case can::MessageKind::gate_command:
      if (can::decode(frame, gate)) {
        stats.indicator_seen = true;
        return Heard::gate;
      }
      break;
    case can::MessageKind::indicator_status: {
      can::IndicatorStatusMessage status;
      if (can::decode(frame, status)) {
        stats.indicator_seen = true;
        stats.indicator_weight_100mg = status.weight_100mg;
        return Heard::other;
      }
      break;
    }
    case can::MessageKind::heartbeat: {
      can::HeartbeatMessage beat;
      if (can::decode(frame, beat)) {
        if (beat.node != can::kNodeIndicator) return Heard::other;
        stats.indicator_seen = true;
        if (verbose) std::fprintf(stderr, "plant: heartbeat of the indicator, state 0x%02x\n", beat.nmt_state);
        return beat.nmt_state == can::kNmtStopped ? Heard::stopped : Heard::other;
      }
      break;
    }
    case can::MessageKind::load_cell_sample:
    case can::MessageKind::valve_feedback:
    case can::MessageKind::gate_feedback:
      return Heard::other;  // our own frames, echoed by a bus
    case can::MessageKind::unknown:
      if (frame.extended || frame.remote) return Heard::other;
      if (ingredient_of(frame.id) != 0) {
        if (decode_ingredient(frame, ingredient)) {
          stats.indicator_seen = true;
          return Heard::ingredient;
        }
        break;  // malformed
      }
      return Heard::other;  // including our own ingredient feedback, echoed by a bus
  }
  ++stats.malformed;
  return Heard::other;
}

int wait_for_indicator(CanTransport& link, const Options& options, Stats& stats) {
  const auto deadline = Clock::now() + std::chrono::duration<double>(options.wait_s);
  can::ValveCommandMessage ignored;
  can::GateCommandMessage ignored_gate;
  IngredientCommand ignored_ingredient;
  while (!stats.indicator_seen) {
    if (g_stop) return 1;
    if (Clock::now() > deadline) {
      std::fprintf(stderr, "dynweigh plant: no indicator heard on %s within %.0f s\n", link.name().c_str(), options.wait_s);
      return 1;
    }
    const Heard heard = listen(link, 100, stats, ignored, ignored_gate, ignored_ingredient, options.verbose);
    if (heard == Heard::closed) {
      std::fprintf(stderr, "dynweigh plant: %s closed before the indicator was heard\n", link.name().c_str());
      return 1;
    }
  }
  return 0;
}

void send_heartbeats(CanTransport& link, std::uint8_t state, std::size_t ingredients) {
  link.send(can::encode(can::HeartbeatMessage{can::kNodeLoadCell, state}));
  link.send(can::encode(can::HeartbeatMessage{can::kNodeValve, state}));
  for (std::size_t i = 1; i < ingredients; ++i) {
    link.send(can::encode(can::HeartbeatMessage{std::uint8_t(can::kNodeValve + i), state}));
  }
  link.send(can::encode(can::HeartbeatMessage{can::kNodeGate, state}));
}

bool send_ingredient_feedback(CanTransport& link, const Modules& modules) {
  for (std::size_t i = 1; i < modules.ingredients(); ++i) {
    if (!link.send(encode_ingredient_feedback(i, modules.ingredient_feedback(i)))) return false;
  }
  return true;
}

bool send_jiffy(CanTransport& link, Modules& modules, std::uint32_t k, can::LoadCellSampleMessage& sample) {
  if (k % 10 == 0) send_heartbeats(link, can::kNmtOperational, modules.ingredients());  // every 100 ms of plant time
  sample = modules.sample(k);
  // Feedback first: it is latched when the sample starts the indicator's jiffy.
  return link.send(can::encode(modules.feedback())) && send_ingredient_feedback(link, modules) &&
         link.send(can::encode(modules.gate_feedback())) && link.send(can::encode(sample));
}

int run_lockstep(CanTransport& link, const Options& options, Modules& modules, Stats& stats) {
  for (std::uint32_t k = 0;; ++k) {
    if (g_stop) return stats.end = "signal", 0;
    if (options.jiffies && k >= options.jiffies) return stats.end = "jiffies", 0;
    if (!modules.has_sample(k)) return stats.end = "replay_end", 0;
    can::LoadCellSampleMessage sample;
    if (!send_jiffy(link, modules, k, sample)) return stats.end = "link_closed", 0;
    const auto deadline = Clock::now() + std::chrono::duration<double>(options.timeout_s);
    can::ValveCommandMessage command;
    can::GateCommandMessage gate;
    IngredientCommand ingredient;
    for (;;) {
      const Heard heard = listen(link, 100, stats, command, gate, ingredient, options.verbose);
      if (heard == Heard::gate) {  // the same jiffy's, before its 0x220
        modules.command_gate(gate.command, stats);
        continue;
      }
      if (heard == Heard::ingredient) {  // likewise
        modules.command_ingredient(ingredient.ingredient, static_cast<sim::ValveCommand>(ingredient.message.command),
                                   ingredient.message.delay_100us * 1e-4, stats);
        continue;
      }
      if (heard == Heard::answer) {
        ++stats.answers;
        if (command.counter == sample.counter) break;
        ++stats.late_answers;
        continue;
      }
      if (heard == Heard::stopped) return stats.end = "indicator_stopped", 0;
      if (heard == Heard::closed) return stats.end = "link_closed", 0;
      if (g_stop) return stats.end = "signal", 0;
      if (Clock::now() > deadline) {
        modules.command(sim::ValveCommand::closed, 0.0, stats, k);  // fail-safe
        modules.close_ingredients();
        modules.command_gate(0, stats);
        ++stats.watchdog_closes;
        std::fprintf(stderr, "dynweigh plant: no answer to sample %u within %.0f s\n", unsigned(sample.counter), options.timeout_s);
        stats.end = "timeout";
        return 1;
      }
    }
    modules.command(static_cast<sim::ValveCommand>(command.command), command.delay_100us * 1e-4, stats, k);
    modules.advance();
    ++stats.jiffies;
  }
}

int run_realtime(CanTransport& link, const Options& options, Modules& modules, Stats& stats) {
  const int timer = ::timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC);
  if (timer < 0) throw std::runtime_error("timerfd_create failed");
  itimerspec period{};
  period.it_value.tv_nsec = 10000000L;
  period.it_interval.tv_nsec = 10000000L;
  ::timerfd_settime(timer, 0, &period, nullptr);
  std::uint32_t last_command_jiffy = 0;
  bool watchdog_tripped = false;
  std::uint32_t k = 0;
  auto finish = [&](const char* why) {
    ::close(timer);
    stats.end = why;
    return 0;
  };
  can::LoadCellSampleMessage sample;
  if (!send_jiffy(link, modules, k, sample)) return finish("link_closed");
  for (;;) {
    if (g_stop) return finish("signal");
    pollfd fds[2] = {{timer, POLLIN, 0}, {link.fd(), POLLIN, 0}};
    if (!link.has_buffered_input() && ::poll(fds, 2, 100) <= 0) continue;
    if (link.has_buffered_input() || (fds[1].revents & (POLLIN | POLLHUP | POLLERR))) {
      can::ValveCommandMessage command;
      can::GateCommandMessage gate;
      IngredientCommand ingredient;
      const Heard heard = listen(link, 0, stats, command, gate, ingredient, options.verbose);
      if (heard == Heard::gate) modules.command_gate(gate.command, stats);
      if (heard == Heard::ingredient) {
        modules.command_ingredient(ingredient.ingredient, static_cast<sim::ValveCommand>(ingredient.message.command),
                                   ingredient.message.delay_100us * 1e-4, stats);
      }
      if (heard == Heard::stopped) return finish("indicator_stopped");
      if (heard == Heard::closed) return finish("link_closed");
      if (heard == Heard::answer) {
        ++stats.answers;
        last_command_jiffy = k;
        watchdog_tripped = false;
        modules.command(static_cast<sim::ValveCommand>(command.command), command.delay_100us * 1e-4, stats, k);
      }
    }
    if (fds[0].revents & POLLIN) {
      std::uint64_t expirations = 0;
      if (::read(timer, &expirations, sizeof expirations) != ssize_t(sizeof expirations)) continue;
      for (std::uint64_t i = 0; i < expirations; ++i) {  // a late process catches up, plant time stays true
        modules.advance();
        ++k;
        ++stats.jiffies;
      }
      if (!watchdog_tripped && k - last_command_jiffy >= std::uint32_t(kWatchdogJiffies)) {
        modules.command(sim::ValveCommand::closed, 0.0, stats, k);
        modules.close_ingredients();     // the ingredient modules' watchdogs too
        modules.command_gate(0, stats);  // the gate module's watchdog too
        ++stats.watchdog_closes;
        watchdog_tripped = true;
      }
      if (options.jiffies && k >= options.jiffies) return finish("jiffies");
      if (!modules.has_sample(k)) return finish("replay_end");
      if (!send_jiffy(link, modules, k, sample)) return finish("link_closed");
    }
  }
}

void print_summary(const Stats& stats, const std::optional<sim::Plant>& plant, const std::string& transport) {
  std::printf("transport=%s\n", transport.c_str());
  std::printf("end=%s\n", stats.end);
  std::printf("jiffies=%u\n", stats.jiffies);
  std::printf("answers=%u\n", stats.answers);
  std::printf("late_answers=%u\n", stats.late_answers);
  std::printf("malformed_frames=%u\n", stats.malformed);
  std::printf("watchdog_closes=%u\n", stats.watchdog_closes);
  std::printf("valve_opens=%u\n", stats.valve_opens);
  std::printf("gate_opens=%u\n", stats.gate_opens);
  std::printf("ingredient_commands=%u\n", stats.ingredient_commands);
  std::printf("ignored_ingredient_commands=%u\n", stats.ignored_ingredient_commands);
  std::printf("first_open_jiffy=%ld\n", stats.first_open_jiffy);
  std::printf("last_close_jiffy=%ld\n", stats.last_close_jiffy);
  std::printf("indicator_weight_g=%.1f\n", stats.indicator_weight_100mg / 10.0);
  if (plant) {
    const sim::PlantTruth& t = plant->truth();
    std::printf("final_static_kg=%.6f\n", t.static_kg);
    std::printf("in_flight_kg=%.6f\n", t.in_flight_kg);
    std::printf("released_kg=%.6f\n", t.released_kg);
    std::printf("silo_kg=%.6f\n", t.silo_kg);
    std::printf("refilled_kg=%.6f\n", t.refilled_kg);
    std::printf("discharged_kg=%.6f\n", t.discharged_kg);
    std::printf("plant_time_s=%.3f\n", t.time_s);
    for (std::size_t i = 1; i < plant->ingredient_count(); ++i) {
      const sim::IngredientTruth& own = t.ingredients[i];
      std::printf("ingredient%zu_released_kg=%.6f\n", i, own.released_kg);
      std::printf("ingredient%zu_silo_kg=%.6f\n", i, own.silo_kg);
    }
  }
  std::fflush(stdout);
}

}  // namespace

int run_plant_command(int argc, char** argv) {
  Options options;
  CLI::App app{"dynweigh plant: the simulator as the load-cell (0x190), valve (0x220/0x1A0) and discharge gate\n"
               "(0x228/0x1A8) modules of docs/can-protocol.md on a CAN transport. Lockstep by default: sample k goes\n"
               "out, the plant waits for the 0x220 carrying counter k, applies it with its delay, advances one jiffy. Prints key=value\n"
               "lines at the end (final_static_kg= is the plant's truth).",
               "dynweigh plant"};
  app.add_option("--can", options.transport,
                 "socketcan:<ifname> | udp:<bind_port>@<peer_host>:<peer_port> | slcan:<tty, pty or unix socket>")
      ->required();
  app.add_option("--scene", options.scene, "scene name or JSON file")->capture_default_str();
  app.add_option("--seed", options.seed, "seed of the plant's disturbances")->capture_default_str();
  app.add_flag("--realtime", options.realtime, "a sample every 10 ms of wall time; the indicator is not waited for");
  app.add_option("--replay", options.replay,
                 "play recorded raw samples instead of the simulator: a readtestdata capture, a CSV with a raw column "
                 "or a dynweigh-fw --record inputs recording");
  app.add_option("--jiffies", options.jiffies, "stop after this many samples (0: until the indicator stops)")
      ->capture_default_str();
  app.add_option("--wait", options.wait_s, "seconds to wait for the indicator to be heard")
      ->capture_default_str()
      ->check(tools::FiniteRange(0.0, 86400.0));
  app.add_option("--timeout", options.timeout_s, "lockstep: seconds to wait for an answer before giving up")
      ->capture_default_str()
      ->check(tools::FiniteRange(0.01, 86400.0));
  app.add_flag("--verbose", options.verbose, "log protocol events on stderr");
  if (const auto exit_status = tools::parse_command_line(app, argc, argv, "dynweigh plant")) return *exit_status;

  try {
    std::optional<sim::Plant> plant;
    std::vector<std::int32_t> replay;
    if (!options.replay.empty()) {
      for (const tools::RecordedSample& sample : tools::load_recorded_samples(options.replay).samples) {
        replay.push_back(sample.raw_counts);
      }
    } else {
      std::optional<sim::Scene> scene = sim::scene_by_name(options.scene);
      if (!scene) {
        std::fprintf(stderr, "dynweigh plant: unknown scene '%s'\n", options.scene.c_str());
        return 2;
      }
      plant.emplace(*scene, options.seed);
    }
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    std::signal(SIGPIPE, SIG_IGN);
    const std::unique_ptr<CanTransport> link = hal::linux_can::open_can_transport(options.transport);
    std::printf("plant=ready transport=%s\n", link->name().c_str());
    std::fflush(stdout);
    Modules modules(options, plant, replay);
    Stats stats;
    if (!options.realtime && wait_for_indicator(*link, options, stats) != 0) return 1;
    const int status = options.realtime ? run_realtime(*link, options, modules, stats)
                                        : run_lockstep(*link, options, modules, stats);
    send_heartbeats(*link, can::kNmtStopped, modules.ingredients());  // the indicator learns that no sample will come
    if (!replay.empty()) std::printf("replay_samples=%zu\n", replay.size());
    print_summary(stats, plant, link->name());
    return status;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dynweigh plant: %s\n", e.what());
    return 1;
  }
}
