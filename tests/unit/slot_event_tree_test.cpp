// The timed interleaved mode's event queue gives the events in EventWheel's slot order,
// far events included, for the mode's pattern (take the next event, then set or clear its slot).
#include "tier/slot_event_tree.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "model/event_wheel.h"

namespace rtusim {
namespace {

TEST(SlotEventTreeTest, TakesEventsInEventWheelSlotOrder) {
  std::mt19937_64 rng(11);
  for (uint32_t slots : {1u, 3u, 32u, 100u}) {
    EventWheel wheel(slots, /*slot_order=*/true);
    SlotEventTree tree(slots);
    for (uint32_t s = 0; s < slots; ++s) {
      const uint64_t c = rng() % 3;
      wheel.push(c, s);
      tree.set(s, c);
    }
    size_t taken = 0, far = 0;
    while (!wheel.empty()) {
      ASSERT_FALSE(tree.empty());
      uint64_t wc = 0, tc = 0;
      const uint32_t ws = wheel.pop(wc);
      const uint32_t ts = tree.take(tc);
      ASSERT_EQ(ts, ws) << "event " << taken << ", " << slots << " slots";
      ASSERT_EQ(tc, wc) << "event " << taken;
      ++taken;
      if (taken > 20000) {  // drain
        tree.clear(ts);
        continue;
      }
      // Next event of the slot: mostly near, ties with others, sometimes beyond the wheel (far,
      // and landing on the cycles near events reach later).
      const uint64_t r = rng() % 16;
      const uint64_t c = r == 0   ? wc + EventWheel::kWheelCycles + rng() % 4
                         : r == 1 ? wc + EventWheel::kWheelCycles - 1 - rng() % 2
                                  : wc + rng() % 5;
      far += c >= wc + EventWheel::kWheelCycles;
      wheel.push(c, ws);
      tree.set(ws, c);
    }
    EXPECT_TRUE(tree.empty());
    EXPECT_GT(far, 100u);
  }
}

TEST(SlotEventTreeTest, ClearRemovesOnlyThatSlot) {
  SlotEventTree tree(5);
  tree.set(4, 10);
  tree.set(2, 10);
  tree.set(0, 12);
  uint64_t c = 0;
  EXPECT_EQ(tree.take(c), 2u);
  EXPECT_EQ(c, 10u);
  tree.clear(2);
  EXPECT_EQ(tree.take(c), 4u);
  tree.clear(4);
  EXPECT_EQ(tree.take(c), 0u);
  EXPECT_EQ(c, 12u);
  tree.clear(0);
  EXPECT_TRUE(tree.empty());
}

}  // namespace
}  // namespace rtusim
