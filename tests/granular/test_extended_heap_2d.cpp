// The thesis' extended 2D heap: grains roll while free to move, fill holes first, and the pile
// keeps its critical slope.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

#include "dynweigh/granular/extended_heap_2d.hpp"

using namespace dynweigh::granular;

TEST(ExtendedHeap2d, CentreDropsBuildAHeapNoSteeperThanCritical) {
  ExtendedHeap2d heap(61, 2, HeapEdges::open_floor);
  Random random(3);
  std::int64_t lost = 0;
  for (int i = 0; i < 3000; ++i) lost += heap.add_grain(heap.centre_column(), random).grains_lost;
  EXPECT_EQ(heap.total_grains() + lost, 3000);
  const auto& h = heap.heights();
  for (int c = 0; c + 1 < heap.columns(); ++c) {
    ASSERT_LE(std::abs(h[c] - h[c + 1]), heap.critical_step()) << "column " << c;
  }
  EXPECT_EQ(heap.max_height(), h[static_cast<std::size_t>(heap.centre_column())]);
  EXPECT_GT(heap.rolling_moves(), 0);
}

TEST(ExtendedHeap2d, ClosedContainerKeepsEveryGrain) {
  ExtendedHeap2d heap(21, 3, HeapEdges::closed_container);
  Random random(5);
  std::int64_t lost = 0;
  std::int64_t moves = 0;
  for (int i = 0; i < 2000; ++i) {
    const Avalanche a = heap.add_grain(heap.centre_column(), random);
    lost += a.grains_lost;
    moves += a.size;
  }
  EXPECT_EQ(lost, 0);
  EXPECT_EQ(heap.total_grains(), 2000);
  EXPECT_EQ(moves, heap.rolling_moves());
  // A full container is level to within the critical step.
  const auto& h = heap.heights();
  EXPECT_LT(*std::max_element(h.begin(), h.end()) - *std::min_element(h.begin(), h.end()),
            heap.critical_step() * heap.columns() / 2);
}

TEST(ExtendedHeap2d, HolesAreFilledFirst) {
  // A flat floor with one pit next to the drop column: the grain goes into the pit although the
  // step (1) is well below the critical step (4).
  ExtendedHeap2d heap(5, 4, HeapEdges::closed_container);
  Random random(1);
  for (int c : {0, 1, 3, 4}) heap.add_grain(c, random);
  heap.add_grain(2, random);  // fills column 2; floor is flat at height 1 now
  ASSERT_EQ(heap.heights(), (std::vector<int>{1, 1, 1, 1, 1}));
  heap.add_grain(0, random);
  heap.add_grain(1, random);
  heap.add_grain(4, random);  // heights 2 2 1 1 2: column 3 is not a pit (column 2 is as low)
  heap.add_grain(2, random);  // 2 2 2 1 2: column 3 is now a pit
  heap.add_grain(2, random);  // lands on column 2 (height 2) next to the pit: rolls into it
  EXPECT_EQ(heap.heights(), (std::vector<int>{2, 2, 2, 2, 2}));
}
