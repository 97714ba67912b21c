// The timed interleaved mode's event wheel gives the events in the event tree's order (EventWheel's
// slot order), far events included, for the mode's pattern (take the next event, then set it again
// or clear its slot).
#include "tier/slot_event_wheel.h"

#include <gtest/gtest.h>

#include <random>

#include "tier/slot_event_tree.h"

namespace rtusim {
namespace {

template <int kWords>
void expect_tree_order(uint32_t slots, uint64_t seed) {
  std::mt19937_64 rng(seed);
  SlotEventTree tree(slots);
  SlotEventWheel<kWords> wheel(slots);
  for (uint32_t s = 0; s < slots; ++s) {
    const uint64_t c = rng() % 3;
    tree.set(s, c);
    wheel.set(s, c);
  }
  size_t taken = 0, far = 0, wraps = 0;
  uint32_t ts = 0, ws = 0;
  uint64_t tc = 0, wc = 0;
  while (tree.take(ts, tc)) {
    ASSERT_TRUE(wheel.take(ws, wc));
    ASSERT_EQ(ws, ts) << "event " << taken << ", " << slots << " slots";
    ASSERT_EQ(wc, tc) << "event " << taken;
    ++taken;
    if (taken > 30000) {  // drain
      tree.clear(ts);
      wheel.clear(ws);
      continue;
    }
    // Next event of the slot: mostly near, ties with others, sometimes far (and landing on the
    // cycles near events reach later), sometimes across the wheel's turn.
    const uint64_t r = rng() % 16;
    const uint64_t c = r == 0   ? tc + SlotEventTree::kFarCycles + rng() % 4
                       : r == 1 ? tc + SlotEventTree::kFarCycles - 1 - rng() % 2
                       : r == 2 ? tc + rng() % 700
                                : tc + rng() % 5;
    far += c >= tc + SlotEventTree::kFarCycles;
    wraps += (c & (SlotEventTree::kFarCycles - 1)) < (tc & (SlotEventTree::kFarCycles - 1));
    tree.set(ts, c);
    wheel.set(ws, c);
  }
  EXPECT_FALSE(wheel.take(ws, wc));
  EXPECT_GT(far, 100u);
  EXPECT_GT(wraps, 100u);
}

TEST(SlotEventWheelTest, TakesEventsInTheTreesOrder) {
  for (uint32_t slots : {1u, 3u, 32u, 64u}) expect_tree_order<1>(slots, 11 + slots);
  for (uint32_t slots : {65u, 100u, 128u}) expect_tree_order<2>(slots, 7 + slots);
}

TEST(SlotEventWheelTest, RejectsTooManySlots) {
  EXPECT_THROW(SlotEventWheel<1>(65), std::logic_error);
  EXPECT_NO_THROW(SlotEventWheel<2>(128));
}

}  // namespace
}  // namespace rtusim
