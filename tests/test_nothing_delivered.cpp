// A dose that delivers nothing is a fault, whatever the strategy: from a silo that is
// empty, or runs dry, no dose ends in `OK` with no more than its own OIML R61 X(5) limit delivered.
#include <gtest/gtest.h>

#include <string>

#include "support/console_session.hpp"

namespace dynweigh::testing {
namespace {

sim::Scene scene_with_silo(double fill_kg) {
  sim::Scene scene = sim::default_scene();
  scene.silo.fill_kg = fill_kg;
  return scene;
}

// Each strategy doses from the empty silo in turn, `clearfault` between: a named fault, the valve
// closed, the fault latched in `status`, and never a result.
void expect_no_flow_from(ConsoleSession& c) {
  for (const char* strategy : {"model", "learn", "preact", "twostage", "pac", "flowpreact"}) {
    SCOPED_TRACE(strategy);
    const std::string answer = c.run({std::string("dose 3000 ") + strategy});
    EXPECT_EQ(answer, "ERR 4 fault no_flow\n");
    EXPECT_EQ(answer.find("OK"), std::string::npos);
    c.idle(50);
    EXPECT_EQ(c.session().plant().truth().stroke, 0.0) << "the valve must be closed";
    const std::string status = c.run({"status"});
    EXPECT_NE(status.find("fault=no_flow"), std::string::npos) << status;
    EXPECT_NE(status.find("valve=0"), std::string::npos) << status;
    EXPECT_EQ(c.run({"clearfault"}), "OK\n");
  }
}

TEST(NothingDelivered, EveryStrategyFromAnEmptySiloFaultsNoFlow) {
  ConsoleSession c(scene_with_silo(0.0));
  c.idle(20);
  expect_no_flow_from(c);
}

// The silo runs dry during a fill: that dose faults (whatever it names), and so does every dose after.
TEST(NothingDelivered, ASiloRunDryFaultsEveryStrategyAfterwards) {
  ConsoleSession c(scene_with_silo(4.0));
  c.idle(20);
  EXPECT_NE(c.run({"dose 3000"}).find("RESULT"), std::string::npos);
  const std::string dry = c.run({"dose 3000"});
  EXPECT_EQ(dry.rfind("ERR 4 fault ", 0), 0u) << dry;
  EXPECT_EQ(c.run({"clearfault"}), "OK\n");
  c.idle(300);
  expect_no_flow_from(c);
}

}  // namespace
}  // namespace dynweigh::testing
