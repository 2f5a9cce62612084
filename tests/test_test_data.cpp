// `starttestdata 50 600` then `readtestdata`, as the thesis' indicator did (the thesis' section 2.2).
#include <gtest/gtest.h>

#include "support/console_session.hpp"

namespace dynweigh::testing {
namespace {

struct Record {
  long jiffy, raw, filtered, marker;
};

std::vector<Record> parse_records(const std::string& output) {
  std::vector<Record> records;
  for (const auto& line : lines_of(output)) {
    Record r{};
    std::istringstream in(line);
    if (in >> r.jiffy >> r.raw >> r.filtered >> r.marker) records.push_back(r);
  }
  return records;
}

TEST(TestData, StartTestData50To600RecordsTheValveScheduleAndTheFill) {
  ConsoleSession c;
  EXPECT_EQ(c.run({"starttestdata 50 600"}), "OK\n");
  const std::string out = c.run({"readtestdata"});
  const auto lines = lines_of(out);
  ASSERT_EQ(lines.size(), 1001u);
  EXPECT_EQ(lines.back(), "OK");
  const auto records = parse_records(out);
  ASSERT_EQ(records.size(), 1000u);
  for (long j = 0; j < 1000; ++j) {
    EXPECT_EQ(records[j].jiffy, j);
    EXPECT_EQ(records[j].marker, j < 50 ? 0 : (j < 600 ? 2 : 0)) << "jiffy " << j;
  }
  // Nothing lands before the valve's dead time and the fall: about 0.5 s after opening.
  EXPECT_LE(std::abs(records[60].filtered), 2);
  // Then the filtered weight rises ...
  EXPECT_GT(records[300].filtered, records[200].filtered + 1000);
  // ... and settles near the plant's static mass (5.5 s of 2.4 kg/s, about 13 kg).
  const double truth_g = c.session().plant().truth().static_kg * 1000.0;
  EXPECT_GT(truth_g, 12000.0);
  EXPECT_NEAR(double(records[999].filtered), truth_g, 10.0);
  // Raw counts follow the load cell, 1 count per gram: averaged over the last second, where the
  // loaded platform still rings a little.
  double raw_mean = 0.0;
  for (long j = 900; j < 1000; ++j) raw_mean += double(records[j].raw - records[0].raw) / 100.0;
  EXPECT_NEAR(raw_mean, truth_g, 10.0);
}

TEST(TestData, ManualCycleRecordsTheValveAsItIs) {
  ConsoleSession c;
  c.run({"valve 1"});
  EXPECT_EQ(c.run({"starttestdata"}), "OK\n");
  const auto records = parse_records(c.run({"readtestdata"}));
  ASSERT_EQ(records.size(), 1000u);
  for (const auto& r : records) EXPECT_EQ(r.marker, 1);
}

TEST(TestData, ADoseIsRecordedToo) {
  ConsoleSession c;
  c.idle(60);  // the scale at rest, so the dose opens at once
  c.run({"dose 2000"});
  const auto records = parse_records(c.run({"readtestdata"}));
  ASSERT_EQ(records.size(), 1000u);
  EXPECT_EQ(records[0].marker, 2);
  EXPECT_EQ(records[999].marker, 0);
}

}  // namespace
}  // namespace dynweigh::testing
