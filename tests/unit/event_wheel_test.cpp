// The unit's event queue: time order, push order or slot order within a cycle, far events.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <tuple>
#include <vector>

#include "model/event_wheel.h"

namespace rtusim {
namespace {

std::vector<std::pair<uint64_t, uint32_t>> drain(EventWheel& w) {
  std::vector<std::pair<uint64_t, uint32_t>> out;
  while (!w.empty()) {
    uint64_t c = 0;
    const uint32_t s = w.pop(c);
    out.push_back({c, s});
  }
  return out;
}

TEST(EventWheelTest, TiesComeInPushOrderByDefault) {
  EventWheel w(8);
  w.push(5, 3);
  w.push(5, 1);
  w.push(4, 7);
  w.push(5, 2);
  const std::vector<std::pair<uint64_t, uint32_t>> want = {{4, 7}, {5, 3}, {5, 1}, {5, 2}};
  EXPECT_EQ(drain(w), want);
}

TEST(EventWheelTest, SlotOrderSortsTiesWhateverThePushOrder) {
  // Random pushes (one event per slot, some beyond the wheel): the pops are sorted by
  // (cycle, slot), for every push order.
  std::mt19937 rng(7);
  for (int round = 0; round < 50; ++round) {
    EventWheel w(64, /*slot_order=*/true);
    std::vector<std::pair<uint64_t, uint32_t>> want;
    std::vector<uint32_t> slots(64);
    for (uint32_t i = 0; i < 64; ++i) slots[i] = i;
    std::shuffle(slots.begin(), slots.end(), rng);
    for (uint32_t s : slots) {
      const uint64_t c = rng() % 4 == 0 ? EventWheel::kWheelCycles + rng() % 5 : rng() % 6;
      w.push(c, s);
      want.push_back({c, s});
    }
    std::sort(want.begin(), want.end());
    EXPECT_EQ(drain(w), want) << "round " << round;
  }
}

}  // namespace
}  // namespace rtusim
