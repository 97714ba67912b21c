// The traversal unit's merged queue gives its entries in the order of the two EventWheels it
// replaced, taken together as the unit took them (arrivals of a cycle before its events; far
// entries of each kind first), for random interleavings of pushes and pops.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <tuple>
#include <vector>

#include "model/event_wheel.h"
#include "model/unit_queue.h"

namespace rtusim {
namespace {

struct Taken {
  uint64_t cycle;
  uint32_t slot;
  bool arrival;
  bool operator==(const Taken&) const = default;
};

// The two wheels as the unit's run loop took them: the earlier cycle, an arrival on a tie.
Taken take(EventWheel& arrivals, EventWheel& events) {
  const uint64_t a = arrivals.empty() ? ~uint64_t{0} : arrivals.top_cycle();
  const uint64_t e = events.empty() ? ~uint64_t{0} : events.top_cycle();
  uint64_t c = 0;
  if (a <= e) {
    const uint32_t s = arrivals.pop(c);
    return {c, s, true};
  }
  const uint32_t s = events.pop(c);
  return {c, s, false};
}

TEST(UnitQueueTest, TakesEntriesAsTwoWheelsTakenTogether) {
  constexpr uint32_t kSlots = 48;
  std::mt19937 rng(11);
  for (int round = 0; round < 40; ++round) {
    EventWheel arrivals(kSlots, /*slot_order=*/true), events(kSlots);
    UnitQueue queue(kSlots);
    std::vector<uint32_t> idle(kSlots);
    for (uint32_t i = 0; i < kSlots; ++i) idle[i] = i;
    uint64_t now = 0;
    for (int op = 0; op < 4000; ++op) {
      // Push while idle slots are left (more often than popping), else pop.
      if (!idle.empty() && (rng() % 3 != 0 || queue.empty())) {
        const size_t k = rng() % idle.size();
        const uint32_t slot = idle[k];
        idle.erase(idle.begin() + static_cast<std::ptrdiff_t>(k));
        const uint32_t r = rng() % 16;
        const uint64_t cycle = r == 0   ? now + UnitQueue::kWheelCycles + rng() % 3
                               : r == 1 ? now + UnitQueue::kWheelCycles - 1 - rng() % 2
                                        : now + rng() % 4;
        if (rng() % 2) {
          arrivals.push(cycle, slot);
          queue.push_arrival(cycle, slot);
        } else {
          events.push(cycle, slot);
          queue.push_event(cycle, slot);
        }
        continue;
      }
      ASSERT_FALSE(queue.empty());
      const Taken want = take(arrivals, events);
      Taken got{};
      got.slot = queue.pop(got.cycle, got.arrival);
      ASSERT_EQ(got, want) << "round " << round << " op " << op;
      now = got.cycle;
      idle.push_back(got.slot);
    }
    while (!queue.empty()) {
      const Taken want = take(arrivals, events);
      Taken got{};
      got.slot = queue.pop(got.cycle, got.arrival);
      ASSERT_EQ(got, want) << "round " << round << " drain";
    }
    EXPECT_TRUE(arrivals.empty() && events.empty());
  }
}

TEST(UnitQueueTest, RefusesAnEntryBehindTheLastTaken) {
  UnitQueue queue(4);
  queue.push_event(10, 0);
  uint64_t c = 0;
  bool arrival = false;
  queue.pop(c, arrival);
  EXPECT_THROW(queue.push_arrival(9, 1), std::logic_error);
}

}  // namespace
}  // namespace rtusim
