// A board's jiffies as run_one_jiffy records them: the Inputs a record holds step a fresh indicator
// to the same Outputs and the same console bytes; the load cell's status bits and the link are what
// the board read, not guessed; and Outputs carry what the tools show.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <deque>
#include <string>
#include <vector>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/hal/control_loop.hpp"
#include "dynweigh/hal/host/inputs_recording.hpp"
#include "dynweigh/hal/host/lockstep_session.hpp"
#include "dynweigh/hal/host/scripted_console.hpp"
#include "dynweigh/sim/scene.hpp"

namespace dynweigh {
namespace {

std::uint32_t bits_of(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

// Keeps every record and each jiffy's console bytes in memory.
class MemoryRecorder final : public hal::JiffyRecorder {
 public:
  struct Kept {
    hal::JiffyRecord record;
    std::string tx;
  };
  void console_sent(const char* data, std::size_t length) override { tx_.append(data, length); }
  void record(const hal::JiffyRecord& jiffy) override {
    kept.push_back({jiffy, tx_});
    tx_.clear();
  }
  std::vector<Kept> kept;

 private:
  std::string tx_;
};

// Runs `lines` on the default plant, one after another as a person waiting for OK would.
void run_lines(hal::host::LockstepSession& session, std::deque<std::string> lines, std::string* printed = nullptr) {
  hal::host::ScriptedConsole console(
      [&lines](std::string& line) {
        if (lines.empty()) return false;
        line = lines.front();
        lines.pop_front();
        return true;
      },
      [printed](const char* data, std::size_t n) {
        if (printed) printed->append(data, n);
      });
  for (int i = 0; i < 20000; ++i) {
    const firmware::Outputs out = session.step(console);
    console.set_indicator_busy(out.busy);
    if (console.input_ended() && !out.busy) return;
  }
  FAIL() << "the lines did not finish";
}

TEST(JiffyRecord, ARecordsInputsReplayToTheSameOutputsAndConsole) {
  hal::host::LockstepSession session(sim::default_scene(), 1);
  const firmware::PersistentSettings start = session.indicator().settings();
  MemoryRecorder recorder;
  session.record_to(&recorder);
  std::string printed;
  run_lines(session, {"dose 2000", "status", "param fall_mm 1500"}, &printed);
  ASSERT_GT(recorder.kept.size(), 100u);

  firmware::Indicator replayed(start);
  std::string replayed_console, recorded_console;
  bool saw_prediction = false;
  for (const MemoryRecorder::Kept& k : recorder.kept) {
    const firmware::Outputs out = replayed.step(k.record.inputs());
    std::string tx;
    char buffer[512];
    for (std::size_t n; (n = replayed.drain_console(buffer, sizeof buffer)) > 0;) tx.append(buffer, n);
    ASSERT_TRUE(hal::host::same_outputs(out, k.record.outputs, /*telemetry=*/true)) << "jiffy " << k.record.jiffy;
    ASSERT_EQ(tx, k.tx) << "jiffy " << k.record.jiffy;
    EXPECT_EQ(k.record.console_tx_length, k.tx.size());
    saw_prediction = saw_prediction || k.record.outputs.predicted_g != 0.0f;
    replayed_console += tx;
    recorded_console += k.tx;
  }
  EXPECT_TRUE(saw_prediction);
  EXPECT_EQ(recorded_console, printed);  // the record holds every byte the console got
  EXPECT_NE(printed.find("RESULT "), std::string::npos) << printed;
}

TEST(JiffyRecord, OutputsCarryWhatTheToolsShow) {
  hal::host::LockstepSession session(sim::default_scene(), 2);
  hal::host::ScriptedConsole console(
      [sent = false](std::string& line) mutable {
        if (sent) return false;
        line = "dose 3000";
        return sent = true;
      },
      [](const char*, std::size_t) {});
  float largest_prediction = 0.0f, largest_net = 0.0f;
  for (int i = 0; i < 20000; ++i) {
    const firmware::Outputs out = session.step(console);
    const firmware::Indicator& indicator = session.indicator();
    ASSERT_EQ(bits_of(out.filtered_g), bits_of(indicator.filtered_weight_g())) << "jiffy " << i;
    ASSERT_EQ(bits_of(out.predicted_g), bits_of(indicator.last_prediction_g())) << "jiffy " << i;
    ASSERT_EQ(out.fault, indicator.fault()) << "jiffy " << i;
    ASSERT_EQ(bits_of(session.last_record().outputs.filtered_g), bits_of(out.filtered_g));
    largest_prediction = std::max(largest_prediction, out.predicted_g);
    largest_net = std::max(largest_net, out.net_g);
    console.set_indicator_busy(out.busy);
    if (console.input_ended() && !out.busy) break;
  }
  // A dose of 3000 g: the prediction and the unfiltered net weight both get there.
  EXPECT_GT(largest_prediction, 2500.0f);
  EXPECT_GT(largest_net, 2900.0f);
}

// A board whose load cell reports what the test says, jiffy by jiffy, over a link the test sets.
class ScriptedLoadCell final : public hal::LoadCellPort {
 public:
  firmware::LoadCellInput read_sample() override {
    firmware::LoadCellInput in{12000 + std::int32_t(k_ % 7), std::uint16_t(k_), 0, k_ % 5 != 4,
                               k_ >= 80 && k_ < 82 ? firmware::LinkStatus::silent : firmware::LinkStatus::ok};
    if (k_ == 120) in.status = firmware::kLoadCellUnderload;
    ++k_;
    return in;
  }

 private:
  std::uint32_t k_ = 0;
};

class StillValve final : public hal::ValvePort {
 public:
  void command(firmware::ValveCommand, std::uint8_t) override {}
  firmware::ValvePosition position() const override { return firmware::ValvePosition::closed; }
};

class SilentConsole final : public hal::ConsolePort {
 public:
  std::size_t read(char*, std::size_t) override { return 0; }
  void write(const char*, std::size_t) override {}
};

TEST(JiffyRecord, StatusBitsAndTheLinkAreRecordedAsTheBoardReadThem) {
  const std::string path = ::testing::TempDir() + "status_bits" + std::to_string(::getpid()) + ".rec";
  hal::host::LockstepSession reference(sim::default_scene(), 1);  // for a calibrated indicator
  const firmware::PersistentSettings settings = reference.indicator().settings();
  firmware::Indicator live(settings);
  ScriptedLoadCell load_cell;
  StillValve valve;
  SilentConsole console;
  std::vector<firmware::Outputs> live_outputs;
  {
    hal::host::InputsRecordingWriter recording(path, live, "test");
    hal::Ports ports{load_cell, valve, console};
    ports.recorder = &recording;
    for (std::uint32_t k = 0; k < 150; ++k) live_outputs.push_back(hal::run_one_jiffy(live, ports, k).outputs);
  }
  ASSERT_EQ(live.fault(), firmware::Fault::underload);

  hal::host::InputsRecordingReader reader(path);
  EXPECT_EQ(reader.version(), hal::host::kInputsRecordingVersion);
  firmware::Indicator replayed(reader.settings());
  std::size_t k = 0;
  for (hal::host::RecordedJiffy j; reader.next(j); ++k) {
    ASSERT_LT(k, live_outputs.size());
    EXPECT_EQ(j.load_cell.status, k == 120 ? firmware::kLoadCellUnderload : 0) << "jiffy " << k;
    EXPECT_EQ(j.load_cell.fresh, k % 5 != 4) << "jiffy " << k;
    EXPECT_EQ(j.load_cell.link, k >= 80 && k < 82 ? firmware::LinkStatus::silent : firmware::LinkStatus::ok);
    ASSERT_TRUE(j.has_telemetry);
    const firmware::Outputs out = replayed.step(j.inputs());
    ASSERT_TRUE(hal::host::same_outputs(out, j.outputs, true)) << "jiffy " << k;
    ASSERT_TRUE(hal::host::same_outputs(out, live_outputs[k], true)) << "jiffy " << k;
  }
  EXPECT_EQ(k, live_outputs.size());
  EXPECT_EQ(replayed.fault(), firmware::Fault::underload);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace dynweigh
