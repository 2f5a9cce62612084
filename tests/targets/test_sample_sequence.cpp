// The load-cell sample counter as the indicator's clock (hal/can/sample_sequence.hpp): duplicates
// run no jiffy, late frames are discarded, lost samples become jiffies without a sample.
#include <gtest/gtest.h>

#include "dynweigh/hal/can/sample_sequence.hpp"

namespace dynweigh::hal::can {
namespace {

TEST(SampleSequence, ConsecutiveCountersAcrossTheWrapAreAcceptedWithNothingMissing) {
  SampleSequence s;
  for (std::uint16_t c = 65530; c != 6; ++c) {
    const SampleSequence::Arrival a = s.arrive(c);
    EXPECT_TRUE(a.accept) << c;
    EXPECT_EQ(a.missing, 0) << c;
  }
  EXPECT_EQ(s.lost() + s.duplicates() + s.out_of_order() + s.restarts(), 0u);
}

TEST(SampleSequence, ADuplicateIsNotCountedTwice) {
  SampleSequence s;
  ASSERT_TRUE(s.arrive(7).accept);
  EXPECT_FALSE(s.arrive(7).accept);
  EXPECT_TRUE(s.arrive(8).accept);
  EXPECT_EQ(s.duplicates(), 1u);
}

TEST(SampleSequence, AFrameOvertakenByANewerOneIsDiscarded) {
  SampleSequence s;
  ASSERT_TRUE(s.arrive(10).accept);
  const SampleSequence::Arrival newer = s.arrive(12);  // 11 is late
  EXPECT_TRUE(newer.accept);
  EXPECT_EQ(newer.missing, 1);
  EXPECT_FALSE(s.arrive(11).accept);
  EXPECT_EQ(s.out_of_order(), 1u);
  EXPECT_EQ(s.arrive(13).missing, 0);
}

TEST(SampleSequence, LostSamplesAreMadeUpLessTheJiffiesATimerAlreadyRan) {
  SampleSequence s;
  ASSERT_TRUE(s.arrive(100).accept);
  EXPECT_EQ(s.arrive(104).missing, 3);
  s.stood_in();
  s.stood_in();
  EXPECT_EQ(s.arrive(108).missing, 1);  // 3 lost, 2 already run without a sample
  s.stood_in();
  s.stood_in();
  s.stood_in();
  EXPECT_EQ(s.arrive(109).missing, 0);  // a late sample: the timer ran ahead, nothing to make up
  EXPECT_EQ(s.lost(), 6u);
}

TEST(SampleSequence, AJumpOutsideTheWindowsIsARestartTakenAsIs) {
  SampleSequence s;
  ASSERT_TRUE(s.arrive(5000).accept);
  const SampleSequence::Arrival back = s.arrive(0);  // the module restarted its count
  EXPECT_TRUE(back.accept);
  EXPECT_EQ(back.missing, 0);
  const SampleSequence::Arrival far = s.arrive(SampleSequence::kMaxFill + 1);
  EXPECT_TRUE(far.accept);
  EXPECT_EQ(far.missing, 0);
  EXPECT_EQ(s.restarts(), 2u);
  EXPECT_TRUE(s.arrive(SampleSequence::kMaxFill + 2).accept);
}

}  // namespace
}  // namespace dynweigh::hal::can
