// dynweigh replay: an inputs recording replays the firmware bit for bit; raw samples replay open
// loop; damaged files are refused with a reason, never believed.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <deque>
#include <fstream>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "dynweigh/hal/host/inputs_recording.hpp"
#include "dynweigh/hal/host/lockstep_session.hpp"
#include "dynweigh/hal/host/scripted_console.hpp"
#include "dynweigh/sim/scene.hpp"
#include "progress_bar.hpp"
#include "recorded_samples.hpp"
#include "replay_run.hpp"

namespace {

using namespace dynweigh;

std::string temp_path(const std::string& name) {
  return (::testing::TempDir() + "dynweigh_test_replay_" + std::to_string(::getpid()) + "_" + name);
}

struct LiveJiffy {
  firmware::Outputs outputs;
  float filtered_g;
  std::int32_t raw;
};

struct LiveRun {
  std::string console;
  std::vector<LiveJiffy> jiffies;
  firmware::PersistentSettings settings;
};

// A live run of `lines` as dynweigh-fw runs it (one line at a time, each once the previous has
// finished), recorded to `path` when it is not empty.
// `rest_jiffies`: how long the scale stands before the first line is sent.
LiveRun run_live(const std::vector<std::string>& lines, const std::string& path, std::uint64_t seed = 1,
                 int rest_jiffies = 0) {
  LiveRun run;
  hal::host::LockstepSession session(sim::default_scene(), seed);
  run.settings = session.indicator().settings();
  std::deque<std::string> script(lines.begin(), lines.end());
  hal::host::ScriptedConsole console(
      [&script](std::string& line) {
        if (script.empty()) return false;
        line = script.front();
        script.pop_front();
        return true;
      },
      [&run](const char* data, std::size_t n) { run.console.append(data, n); });
  std::unique_ptr<hal::host::InputsRecordingWriter> recording;
  console.set_indicator_busy(rest_jiffies > 0);
  if (!path.empty()) {
    recording = std::make_unique<hal::host::InputsRecordingWriter>(path, session.indicator(), "test");
    session.record_to(recording.get());
  }
  for (int i = 0; i < 30000; ++i) {
    const firmware::Outputs out = session.step(console);
    run.jiffies.push_back({out, out.filtered_g, session.last_row().raw});
    console.set_indicator_busy(out.busy || i + 1 < rest_jiffies);  // nothing is sent while the scale rests
    if (console.input_ended() && !out.busy) break;
  }
  return run;
}

struct Replayed {
  std::string console;
  std::vector<tools::ReplayRow> rows;
  tools::ReplaySummary summary;
};

tools::ReplaySinks sinks_into(Replayed& r) {
  tools::ReplaySinks sinks;
  sinks.row = [&r](const tools::ReplayRow& row) { r.rows.push_back(row); };
  sinks.console = [&r](const char* data, std::size_t n) { r.console.append(data, n); };
  return sinks;
}

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_all(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

std::uint32_t bits_of(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

TEST(ReplayInputsRecording, DoseReplaysBitForBit) {
  const std::string path = temp_path("dose.rec");
  const LiveRun live = run_live({"dose 3000"}, path);
  ASSERT_NE(live.console.find("RESULT target=3000"), std::string::npos) << live.console;

  Replayed replayed;
  replayed.summary = tools::replay_inputs_recording(path, {}, sinks_into(replayed));
  EXPECT_EQ(replayed.console, live.console);  // byte for byte
  ASSERT_EQ(replayed.rows.size(), live.jiffies.size());
  for (std::size_t i = 0; i < live.jiffies.size(); ++i) {
    ASSERT_EQ(replayed.rows[i].valve, live.jiffies[i].outputs.valve) << "jiffy " << i;
    ASSERT_EQ(bits_of(replayed.rows[i].filtered_g), bits_of(live.jiffies[i].filtered_g)) << "jiffy " << i;
    ASSERT_EQ(replayed.rows[i].raw_counts, live.jiffies[i].raw) << "jiffy " << i;
  }
  EXPECT_TRUE(replayed.summary.checked);
  EXPECT_EQ(replayed.summary.first_mismatch_jiffy, -1) << replayed.summary.mismatch;
  EXPECT_FALSE(replayed.summary.open_loop);
  ASSERT_EQ(replayed.summary.results.size(), 1u);
  EXPECT_GT(replayed.summary.cutoff_jiffy, 0);
  std::remove(path.c_str());
}

// A console that takes a few bytes a jiffy, as a serial line does: the rest waits in the
// indicator's ring and holds the next command back.
class NarrowConsole final : public hal::ConsolePort {
 public:
  explicit NarrowConsole(std::deque<std::string> lines) : lines_(std::move(lines)) {}
  void set_busy(bool busy) { busy_ = busy; }
  bool done() const { return lines_.empty() && !busy_; }
  std::size_t read(char* destination, std::size_t capacity) override {
    room_ = kBytesPerJiffy;  // a board reads its console first thing in a jiffy
    if (busy_ || lines_.empty()) return 0;
    const std::string line = lines_.front() + "\n";
    lines_.pop_front();
    busy_ = true;
    const std::size_t n = std::min(capacity, line.size());
    std::memcpy(destination, line.data(), n);
    return n;
  }
  void write(const char* data, std::size_t length) override {
    printed.append(data, length);
    room_ -= std::min(room_, length);
  }
  std::size_t writable() const override { return room_; }
  std::string printed;

 private:
  static constexpr std::size_t kBytesPerJiffy = 48;
  std::size_t room_ = kBytesPerJiffy;
  std::deque<std::string> lines_;
  bool busy_ = false;
};

std::string run_narrow(const std::string& record_path) {
  hal::host::LockstepSession session(sim::default_scene(), 4);
  std::unique_ptr<hal::host::InputsRecordingWriter> recording;
  if (!record_path.empty()) {
    recording = std::make_unique<hal::host::InputsRecordingWriter>(record_path, session.indicator(), "test");
    session.record_to(recording.get());
  }
  NarrowConsole console({"param", "dose 2000", "status"});
  for (int i = 0; i < 30000 && !console.done(); ++i) console.set_busy(session.step(console).busy);
  return console.printed;
}

TEST(ReplayInputsRecording, ASlowConsoleRecordsAndReplaysAsItRan) {
  const std::string path = temp_path("narrow.rec");
  const std::string unrecorded = run_narrow("");
  const std::string recorded = run_narrow(path);
  EXPECT_EQ(recorded, unrecorded);  // recording changes nothing the board does
  ASSERT_NE(recorded.find("RESULT target=2000"), std::string::npos) << recorded;
  Replayed replayed;
  replayed.summary = tools::replay_inputs_recording(path, {}, sinks_into(replayed));
  EXPECT_EQ(replayed.summary.first_mismatch_jiffy, -1) << replayed.summary.mismatch;
  EXPECT_EQ(replayed.console, recorded);
  std::remove(path.c_str());
}

TEST(ReplayInputsRecording, SettingsAndConsoleCommandsReplayToo) {
  const std::string path = temp_path("params.rec");
  const LiveRun live = run_live({"param filter avg", "starttestdata 10 200", "status", "readtestdata", "bogus"}, path);
  Replayed replayed;
  replayed.summary = tools::replay_inputs_recording(path, {}, sinks_into(replayed));
  EXPECT_EQ(replayed.console, live.console);
  EXPECT_EQ(replayed.summary.first_mismatch_jiffy, -1) << replayed.summary.mismatch;
  EXPECT_NE(replayed.console.find("ERR 1"), std::string::npos);
  std::remove(path.c_str());
}

TEST(ReplayInputsRecording, AnotherStrategyIsOpenLoopAndSaysSo) {
  const std::string path = temp_path("strategy.rec");
  // `readtestdata` waits for the dose's 1000-jiffy recording: jiffies enough for another strategy's dose.
  // At 5 kg the model's close is measured on a grown stream, as late as preact's would be; in class
  // X(5) it needs no fine feed, whose half-open valve preact would take for one stuck.
  run_live({"param class 5", "dose 5000", "readtestdata"}, path);
  tools::ReplayOptions options;
  options.strategy = firmware::DosingStrategy::preact;
  Replayed replayed;
  replayed.summary = tools::replay_inputs_recording(path, options, sinks_into(replayed));
  EXPECT_TRUE(replayed.summary.open_loop);
  EXPECT_FALSE(replayed.summary.checked);
  EXPECT_EQ(replayed.summary.doses_rewritten, 1u);
  EXPECT_NE(replayed.console.find("strategy=preact"), std::string::npos) << replayed.console;
  std::remove(path.c_str());
}

TEST(ReplayInputsRecording, TruncatedFileIsRefusedWithAReason) {
  const std::string path = temp_path("truncated.rec");
  run_live({"status"}, path);
  const std::string whole = read_all(path);
  for (std::size_t cut : {std::size_t(5), std::size_t(20), whole.size() - 3}) {
    write_all(path, whole.substr(0, cut));
    try {
      Replayed replayed;
      tools::replay_inputs_recording(path, {}, sinks_into(replayed));
      FAIL() << "accepted a file cut at " << cut;
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_TRUE(what.find("truncated") != std::string::npos || what.find("not an inputs") != std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos);
    }
  }
  std::remove(path.c_str());
}

TEST(ReplayInputsRecording, FlippedByteIsCaughtByTheCrc) {
  const std::string path = temp_path("flipped.rec");
  run_live({"dose 1000"}, path);
  std::string bytes = read_all(path);
  bytes[bytes.size() / 2] = char(bytes[bytes.size() / 2] ^ 0x10);
  write_all(path, bytes);
  Replayed replayed;
  EXPECT_THROW(tools::replay_inputs_recording(path, {}, sinks_into(replayed)), std::runtime_error);
  std::remove(path.c_str());
}

TEST(ReplaySamples, OpenLoopReplayOfALiveDoseReachesTheSameCutoff) {
  // The samples of a closed-loop dose, replayed raw with the same command at the same jiffy: the
  // indicator sees what it saw live, so it decides the same, though nothing closes the loop.
  // The scale stands at rest first, so the valve opens in the dose's own jiffy.
  constexpr int kRest = 100;
  const LiveRun live = run_live({"dose 3000"}, "", 1, kRest);
  tools::RecordedSamples samples;
  samples.format = "csv";
  for (const LiveJiffy& j : live.jiffies) samples.samples.push_back({j.raw, int(j.outputs.valve)});
  ASSERT_EQ(samples.first_open_jiffy(), kRest);
  tools::ReplayOptions options;
  options.settings = live.settings;
  options.console_lines = {"dose 3000"};
  Replayed replayed;
  replayed.summary = tools::replay_samples(samples, options, sinks_into(replayed));
  EXPECT_TRUE(replayed.summary.open_loop);
  EXPECT_EQ(replayed.console, live.console);
  for (std::size_t i = 0; i < live.jiffies.size(); ++i) {
    ASSERT_EQ(replayed.rows[i].valve, live.jiffies[i].outputs.valve) << "jiffy " << i;
  }
}

TEST(RecordedSamples, ReadTestDataCaptureIsAcceptedAsIs) {
  const LiveRun live = run_live({"starttestdata 50 600", "readtestdata"}, "");
  const std::string capture = live.console.substr(live.console.find("\n0 ") + 1);  // after starttestdata's OK
  const std::string path = temp_path("capture.txt");
  write_all(path, "\n" + capture + "\n");
  const tools::RecordedSamples samples = tools::load_recorded_samples(path);
  EXPECT_EQ(samples.format, "readtestdata");
  ASSERT_EQ(samples.samples.size(), 1000u);
  EXPECT_EQ(samples.first_open_jiffy(), 50);
  EXPECT_EQ(samples.samples[600].valve, 0);
  std::remove(path.c_str());
}

// The one capture reader (dynweigh replay and dynweigh plant --replay) reads an inputs recording
// too: each jiffy's raw sample and the valve the live run commanded.
TEST(RecordedSamples, AnInputsRecordingGivesEachJiffysSampleAndValve) {
  const std::string path = temp_path("samples.rec");
  const LiveRun live = run_live({"dose 2000"}, path);
  const tools::RecordedSamples samples = tools::load_recorded_samples(path);
  EXPECT_EQ(samples.format, "inputs");
  ASSERT_EQ(samples.samples.size(), live.jiffies.size());
  for (std::size_t i = 0; i < live.jiffies.size(); ++i) {
    ASSERT_EQ(samples.samples[i].raw_counts, live.jiffies[i].raw) << "jiffy " << i;
    ASSERT_EQ(samples.samples[i].valve, int(live.jiffies[i].outputs.valve)) << "jiffy " << i;
  }
  EXPECT_GE(samples.first_open_jiffy(), 0);
  std::remove(path.c_str());
}

// A capture as a terminal keeps it: the commands echoed before the data are skipped, not refused.
TEST(RecordedSamples, ACaptureWithItsCommandsIsRead) {
  const std::string path = temp_path("with_commands.txt");
  write_all(path, "starttestdata 50 600\nOK\nreadtestdata\n0 8000 0 0\n1 8004 2 1\nOK\n"
                  "readtestdata\n0 8010 0 2\n1 8011 0 0\nOK\n");  // and a second printout
  const tools::RecordedSamples samples = tools::load_recorded_samples(path);
  EXPECT_EQ(samples.format, "readtestdata");
  ASSERT_EQ(samples.samples.size(), 4u);
  EXPECT_EQ(samples.samples[1].raw_counts, 8004);
  EXPECT_EQ(samples.samples[1].valve, 1);
  EXPECT_EQ(samples.samples[2].raw_counts, 8010);
  std::remove(path.c_str());
}

TEST(RecordedSamples, MalformedFilesNameTheLine) {
  const std::string path = temp_path("bad.txt");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"0 8000 0 0\n1 8001 0 0\n3 8002 0 0\n", "line 3"},
      {"0 8000 0 0\n1 x 0 0\n", "line 2"},
      {"0 8000 0 7\n", "marker"},
      {"ERR 2 no test data\n", "ERR"},
      {std::string("0 8000 0 0\n\x01\x02\0\xff", 15), "binary"},
      {"a,b\n1,2\n", "raw"},
      {"t,raw\n0,1\n1\n", "fields"},
      {"", "empty"},
      {std::string(5000, '1') + "\n", "longer"},
  };
  for (const auto& [content, expected] : cases) {
    write_all(path, content);
    try {
      tools::load_recorded_samples(path);
      FAIL() << "accepted: " << content.substr(0, 40);
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
  }
  std::remove(path.c_str());
}

TEST(ProgressBar, SilentForTheFirstSecondThenDrawsAndEndsItsLine) {
  ::setenv("DYNWEIGH_PROGRESS", "1", 1);
  ::testing::internal::CaptureStderr();
  {
    tools::ProgressBar bar("work", 100);
    bar.update(10);  // within the first second: nothing
    EXPECT_TRUE(::testing::internal::GetCapturedStderr().empty());
    ::testing::internal::CaptureStderr();
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    bar.update(50);
  }
  const std::string drawn = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(drawn.find("work ["), std::string::npos) << drawn;
  EXPECT_NE(drawn.find("50%"), std::string::npos) << drawn;
  EXPECT_EQ(drawn.back(), '\n');

  ::testing::internal::CaptureStderr();
  {
    tools::ProgressBar quiet("work", 100, /*enabled=*/false);
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    quiet.update(50);
  }
  EXPECT_TRUE(::testing::internal::GetCapturedStderr().empty());
  ::unsetenv("DYNWEIGH_PROGRESS");
}

}  // namespace
