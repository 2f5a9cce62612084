// The tolerance check: the verdict at every band edge, the bands from the OIML R61 class or set by
// hand, and each tol_action through the console on the simulated plant.
#include <gtest/gtest.h>

#include <string>

#include "dynweigh/firmware/tolerance.hpp"
#include "support/console_session.hpp"

namespace dynweigh::testing {
namespace {

using firmware::ToleranceBands;
using firmware::ToleranceVerdict;
using firmware::judge_tolerance;

constexpr float kStep = 0.01f;  // just past an edge

TEST(ToleranceVerdict, EveryBandEdge) {
  const ToleranceBands b{2.0f, 3.0f, 5.0f, 7.0f};  // TL1 TH1 TL2 TH2
  EXPECT_EQ(judge_tolerance(0.0f, b), ToleranceVerdict::ok);
  EXPECT_EQ(judge_tolerance(-2.0f, b), ToleranceVerdict::ok);
  EXPECT_EQ(judge_tolerance(-2.0f - kStep, b), ToleranceVerdict::warn_low);
  EXPECT_EQ(judge_tolerance(-5.0f, b), ToleranceVerdict::warn_low);
  EXPECT_EQ(judge_tolerance(-5.0f - kStep, b), ToleranceVerdict::low);
  EXPECT_EQ(judge_tolerance(3.0f, b), ToleranceVerdict::ok);
  EXPECT_EQ(judge_tolerance(3.0f + kStep, b), ToleranceVerdict::warn_high);
  EXPECT_EQ(judge_tolerance(7.0f, b), ToleranceVerdict::warn_high);
  EXPECT_EQ(judge_tolerance(7.0f + kStep, b), ToleranceVerdict::high);
  EXPECT_EQ(judge_tolerance(-1000.0f, b), ToleranceVerdict::low);
  EXPECT_EQ(judge_tolerance(1000.0f, b), ToleranceVerdict::high);
}

TEST(ToleranceVerdict, AWarningBandWiderThanTheRejectBandNeverHidesAReject) {
  const ToleranceBands b{10.0f, 10.0f, 4.0f, 4.0f};
  EXPECT_EQ(judge_tolerance(-4.0f, b), ToleranceVerdict::ok);
  EXPECT_EQ(judge_tolerance(-4.0f - kStep, b), ToleranceVerdict::low);
  EXPECT_EQ(judge_tolerance(4.0f + kStep, b), ToleranceVerdict::high);
}

TEST(ToleranceBands, FromTheOimlClassAndSetByHand) {
  firmware::Parameters p;
  // 2 kg in X(1): 1.05 % at initial verification (21 g), 1.5 % in service (30 g).
  ToleranceBands b = firmware::tolerance_bands(2000.0f, p);
  EXPECT_FLOAT_EQ(b.warn_low_g, 21.0f);
  EXPECT_FLOAT_EQ(b.warn_high_g, 21.0f);
  EXPECT_FLOAT_EQ(b.reject_low_g, 30.0f);
  EXPECT_FLOAT_EQ(b.reject_high_g, 30.0f);
  ASSERT_TRUE(p.set(firmware::ParameterId::oiml_class, 0.5f));
  b = firmware::tolerance_bands(2000.0f, p);
  EXPECT_FLOAT_EQ(b.warn_low_g, 10.5f);
  EXPECT_FLOAT_EQ(b.reject_high_g, 15.0f);
  ASSERT_TRUE(p.set(firmware::ParameterId::tol_warn_high_g, 4.0f));
  ASSERT_TRUE(p.set(firmware::ParameterId::tol_reject_low_g, 12.0f));
  b = firmware::tolerance_bands(2000.0f, p);
  EXPECT_FLOAT_EQ(b.warn_low_g, 10.5f);  // still the class's
  EXPECT_FLOAT_EQ(b.warn_high_g, 4.0f);
  EXPECT_FLOAT_EQ(b.reject_low_g, 12.0f);
  EXPECT_FLOAT_EQ(b.reject_high_g, 15.0f);
}

// A preact strategy closing 600 g early ends far under a 2 kg target: outside a 5 g reject band.
const std::vector<std::string> kShortFill = {"param preact_g 600", "param tol_reject_low_g 5",
                                             "param tol_warn_low_g 2", "param topup_ms 100"};

std::string line_starting(const std::string& output, const std::string& prefix) {
  for (const std::string& line : lines_of(output)) {
    if (line.rfind(prefix, 0) == 0) return line;
  }
  return "";
}

TEST(ToleranceAction, AcceptReportsTheVerdict) {
  ConsoleSession c;
  c.run(kShortFill);
  const std::string out = c.run({"dose 2000 preact"});
  const std::string result = line_starting(out, "RESULT ");
  ASSERT_FALSE(result.empty()) << out;
  EXPECT_LT(std::stoi(field(result, "error")), -5) << result;
  EXPECT_EQ(field(result, "tolerance"), "low");
  EXPECT_EQ(field(result, "topups"), "0");
  EXPECT_EQ(field(result, "seq"), "1");
  EXPECT_EQ(lines_of(out).back(), "OK");
}

TEST(ToleranceAction, TopupPulsesUntilInsideTheRejectBandOrTopupMax) {
  ConsoleSession c;
  c.run(kShortFill);
  c.run({"param tol_action topup", "param topup_max 20", "param topup_ms 300"});
  const std::string out = c.run({"dose 2000 preact"}, 60000);
  const std::string result = line_starting(out, "RESULT ");
  ASSERT_FALSE(result.empty()) << out;
  const int topups = std::stoi(field(result, "topups"));
  EXPECT_GE(topups, 1) << result;
  EXPECT_LE(topups, 20) << result;
  if (topups < 20) {
    EXPECT_NE(field(result, "tolerance"), "low") << result;
  }
  EXPECT_GE(std::stoi(field(result, "error")), -5) << result;  // topped up past the reject edge
  EXPECT_EQ(lines_of(out).back(), "OK");
  // The valve is closed, the scale idle.
  const std::string status = line_starting(c.run({"status"}), "STATUS");
  EXPECT_EQ(field(status, "state"), "idle");
  EXPECT_EQ(field(status, "valve"), "0");
}

TEST(ToleranceAction, TopupStopsAtTopupMax) {
  ConsoleSession c;
  c.run(kShortFill);
  c.run({"param tol_action topup", "param topup_max 1", "param topup_ms 10"});
  const std::string result = line_starting(c.run({"dose 2000 preact"}, 60000), "RESULT ");
  ASSERT_FALSE(result.empty());
  EXPECT_EQ(field(result, "topups"), "1");
  EXPECT_EQ(field(result, "tolerance"), "low");  // one 10 ms pulse cannot bring 600 g
}

TEST(ToleranceAction, HoldWaitsForTheOperatorThenTopupAndAccept) {
  ConsoleSession c;
  c.run(kShortFill);
  c.run({"param tol_action hold", "param topup_ms 300"});
  const std::string held = c.run({"dose 2000 preact"});
  const std::string hold = line_starting(held, "HOLD ");
  ASSERT_FALSE(hold.empty()) << held;
  EXPECT_EQ(field(hold, "tolerance"), "low");
  EXPECT_EQ(line_starting(held, "RESULT "), "");  // nothing reported or logged yet
  EXPECT_NE(c.run({"status"}).find("state=hold"), std::string::npos);
  EXPECT_EQ(c.run({"dose 100"}), "ERR 3 busy\n");
  EXPECT_EQ(c.run({"log"}), "ERR 3 busy\n");

  const std::string topped = c.run({"topup"}, 60000);
  const std::string again = line_starting(topped, "HOLD ");
  const std::string after = again.empty() ? line_starting(topped, "RESULT ") : again;
  ASSERT_FALSE(after.empty()) << topped;
  EXPECT_GT(std::stoi(field(after, "final")), std::stoi(field(hold, "final"))) << topped;
  EXPECT_EQ(field(after, "topups"), "1");
  if (!again.empty()) {
    const std::string accepted = c.run({"accept"});
    const std::string result = line_starting(accepted, "RESULT ");
    ASSERT_FALSE(result.empty()) << accepted;
    EXPECT_EQ(field(result, "final"), field(again, "final"));
    EXPECT_EQ(field(result, "seq"), "1");
  }
  EXPECT_NE(c.run({"status"}).find("state=idle"), std::string::npos);
  EXPECT_EQ(c.run({"accept"}), "ERR 2 no result held\n");
}

TEST(ToleranceAction, HoldThenAcceptLogsTheResultAsItIs) {
  ConsoleSession c;
  c.run(kShortFill);
  c.run({"param tol_action hold"});
  const std::string hold = line_starting(c.run({"dose 2000 preact"}), "HOLD ");
  ASSERT_FALSE(hold.empty());
  const std::string result = line_starting(c.run({"accept"}), "RESULT ");
  EXPECT_EQ(field(result, "final"), field(hold, "final"));
  EXPECT_EQ(field(result, "tolerance"), "low");
  EXPECT_EQ(field(result, "topups"), "0");
  const std::string log = line_starting(c.run({"log 1"}), "LOG ");
  EXPECT_EQ(field(log, "final"), field(hold, "final"));
  EXPECT_EQ(field(log, "tolerance"), "low");
}

TEST(ToleranceAction, AbortDropsAHeldResult) {
  ConsoleSession c;
  c.run(kShortFill);
  c.run({"param tol_action hold"});
  ASSERT_FALSE(line_starting(c.run({"dose 2000 preact"}), "HOLD ").empty());
  EXPECT_EQ(c.run({"abort"}), "OK\n");
  EXPECT_EQ(c.run({"accept"}), "ERR 2 no result held\n");
  EXPECT_EQ(c.run({"log"}), "OK\n");  // nothing logged
}

}  // namespace
}  // namespace dynweigh::testing
