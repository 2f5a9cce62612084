// The thesis' 1D slope model (eqs. 3.1-3.2) settles into the critical staircase.
#include <gtest/gtest.h>

#include "dynweigh/granular/avalanche_statistics.hpp"
#include "dynweigh/granular/slope_sandpile_1d.hpp"

using namespace dynweigh::granular;

TEST(SlopeSandpile1d, GrainsAtTheWallBuildTheCriticalStaircase) {
  constexpr int kColumns = 20;
  constexpr int kCriticalSlope = 3;
  SlopeSandpile1d pile(kColumns, kCriticalSlope);
  // The staircase holds z_c * N (N + 1) / 2 grains; nothing leaves before it is complete.
  const std::int64_t staircase_grains = std::int64_t{kCriticalSlope} * kColumns * (kColumns + 1) / 2;
  std::int64_t lost = 0;
  for (std::int64_t i = 0; i < staircase_grains; ++i) lost += pile.add_grain(0).grains_lost;
  EXPECT_EQ(lost, 0);
  EXPECT_TRUE(pile.is_critical_staircase());
  EXPECT_EQ(pile.height(0), kCriticalSlope * kColumns);
  EXPECT_EQ(pile.total_grains(), staircase_grains);
}

TEST(SlopeSandpile1d, EachFurtherGrainPassesThroughToTheEdge) {
  constexpr int kColumns = 16;
  SlopeSandpile1d pile(kColumns, 2);
  for (int i = 0; i < 1000; ++i) pile.add_grain(0);
  ASSERT_TRUE(pile.is_critical_staircase());
  for (int i = 0; i < 50; ++i) {
    const Avalanche a = pile.add_grain(0);
    EXPECT_EQ(a.grains_lost, 1);
    EXPECT_EQ(a.size, kColumns);  // every column passes the grain on once
    EXPECT_EQ(a.area, kColumns);
    EXPECT_EQ(a.duration, kColumns);
    EXPECT_TRUE(pile.is_critical_staircase());
  }
}

TEST(SlopeSandpile1d, RandomAdditionAlsoEndsCriticalAndConservesGrains) {
  SlopeSandpile1d pile(12, 2);
  std::uint64_t state = 12345;
  std::int64_t lost = 0;
  for (int i = 0; i < 3000; ++i) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    lost += pile.add_grain(static_cast<int>((state >> 33) % 12)).grains_lost;
    for (int c = 0; c < pile.columns(); ++c) ASSERT_LE(pile.slope(c), pile.critical_slope());
  }
  EXPECT_EQ(pile.total_grains(), 3000 - lost);
  EXPECT_GT(lost, 0);
  // In 1D the only recurrent stable state is the critical staircase (Kadanoff et al. 1989).
  EXPECT_TRUE(pile.is_critical_staircase());
}
