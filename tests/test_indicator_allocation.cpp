// The control loop allocates nothing after start-up: every command a user types, a dose of each
// strategy, a test cycle and its 1000-line printout, run through the board's jiffy with the
// global operator new of this test binary counting. The plant and the console port here allocate
// nothing either, so any count is the indicator's.
#include <gtest/gtest.h>

#include "support/counting_operator_new.hpp"

#include <cstdlib>
#include <cstring>

#include "dynweigh/hal/host/lockstep_session.hpp"
#include "dynweigh/sim/scene.hpp"

using dynweigh::testing::g_allocations;

namespace dynweigh {
namespace {

// A console of fixed buffers: one line in at a time, everything out kept (up to its size).
class FixedConsole final : public hal::ConsolePort {
 public:
  void type(const char* line) {
    pending_ = line;
    left_ = std::strlen(line);
  }
  bool typed() const { return left_ == 0; }
  std::size_t read(char* destination, std::size_t capacity) override {
    const std::size_t n = left_ < capacity ? left_ : capacity;
    std::memcpy(destination, pending_, n);
    pending_ += n;
    left_ -= n;
    return n;
  }
  void write(const char* data, std::size_t length) override {
    written_ += length;
    const std::size_t room = sizeof kept_ - 1 - kept_length_;
    const std::size_t n = length < room ? length : room;
    std::memcpy(kept_ + kept_length_, data, n);
    kept_length_ += n;
    kept_[kept_length_] = '\0';
  }
  const char* kept() const { return kept_; }
  std::size_t written() const { return written_; }

 private:
  const char* pending_ = "";
  std::size_t left_ = 0;
  char kept_[1 << 16] = {};
  std::size_t kept_length_ = 0;
  std::size_t written_ = 0;
};

// Types `line`, then runs jiffies until the command has finished; returns the jiffies it took.
std::uint32_t run_command(hal::host::LockstepSession& session, FixedConsole& console, const char* line) {
  console.type(line);
  for (std::uint32_t jiffy = 1; jiffy <= 30000; ++jiffy) {
    const firmware::Outputs out = session.step(console);
    if (console.typed() && !out.busy && jiffy > 2) return jiffy;
  }
  return 0;
}

TEST(IndicatorAllocation, EveryCommandAndEveryStrategyRunsWithoutAllocating) {
  hal::host::LockstepSession session(sim::default_scene(), 3);
  FixedConsole console;
  const char* const lines[] = {
      "help\n",          "version\n",         "status\n",          "param\n",
      "param filter\n",  "param preact_g 150\n", "estimates\n",    "learn\n",
      "tare\n",          "dose 2000\n",       "dose 1000 preact\n", "dose 1000 twostage\n",
      "dose 1000 learn\n", "starttestdata 50 600\n", "readtestdata\n", "valve 0\n",
      "no_such_command\n", "dose\n",          "param class x\n",   "status\n"};
  const long before = g_allocations.load();
  for (const char* line : lines) {
    EXPECT_GT(run_command(session, console, line), 0u) << line << " did not finish";
  }
  EXPECT_EQ(g_allocations.load() - before, 0) << "the indicator allocated while it ran";
  // It did the work: four RESULT lines and the test cycle's 1000 records came out.
  int results = 0;
  for (const char* p = console.kept(); (p = std::strstr(p, "RESULT ")) != nullptr; ++p) ++results;
  EXPECT_EQ(results, 4) << console.kept();
  EXPECT_GT(console.written(), 1000u * 8u);
}

}  // namespace
}  // namespace dynweigh
