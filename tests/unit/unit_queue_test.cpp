// The traversal unit's merged queue: by cycle; within a cycle the arrivals first, in slot order
// however far ahead each was pushed, then the events in the order of the EventWheel the queue
// replaced (far entries first, by slot, then push order), for random interleavings of pushes
// and pops.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <tuple>
#include <utility>
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

// The reference: arrivals as (cycle, slot) in a set, events in an EventWheel; the earlier
// cycle first, an arrival on a tie.
Taken take(std::set<std::pair<uint64_t, uint32_t>>& arrivals, EventWheel& events) {
  const uint64_t a = arrivals.empty() ? ~uint64_t{0} : arrivals.begin()->first;
  const uint64_t e = events.empty() ? ~uint64_t{0} : events.top_cycle();
  if (a <= e) {
    const auto [c, s] = *arrivals.begin();
    arrivals.erase(arrivals.begin());
    return {c, s, true};
  }
  uint64_t c = 0;
  const uint32_t s = events.pop(c);
  return {c, s, false};
}

TEST(UnitQueueTest, TakesArrivalsBySlotAndEventsAsTheirWheel) {
  constexpr uint32_t kSlots = 48;
  std::mt19937 rng(11);
  for (int round = 0; round < 40; ++round) {
    std::set<std::pair<uint64_t, uint32_t>> arrivals;
    EventWheel events(kSlots);
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
          arrivals.emplace(cycle, slot);
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
