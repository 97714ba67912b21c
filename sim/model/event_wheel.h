// The unit's first event queue: UnitQueue (unit_queue.h) replaced it and keeps its constants
// and first_marked_cycle(); tests use the class as the reference queue. At most one event per
// ray slot, at a cycle no earlier than the last one taken. A timing wheel of one bucket per
// cycle over the next kWheelCycles (FIFO lists threaded through the slots, a bitmap of
// non-empty buckets), plus a heap for the rare event further ahead. Push and pop are O(1) when
// events are dense in time, as they are when the unit is busy; a binary heap costs a
// mispredicted branch per level.
// Events of one cycle come out in push order, or with `slot_order` in slot order (the bucket's
// list is kept sorted: short, one entry per slot due that cycle).
#pragma once
#include <algorithm>
#include <bit>
#include <cstdint>
#include <functional>
#include <queue>
#include <vector>

namespace rtusim {

class EventWheel {
 public:
  static constexpr uint64_t kWheelCycles = 4096;
  static constexpr uint32_t kNone = ~uint32_t{0};
  static constexpr uint32_t kSlotBits = 20;  // far events are packed as cycle << 20 | slot

  explicit EventWheel(uint32_t slots, bool slot_order = false)
      : slot_order_(slot_order),
        link_(slots, kNone), head_(kWheelCycles, kNone), tail_(kWheelCycles, kNone),
        nonempty_(kWheelCycles / 64, 0) {}

  bool empty() const { return count_ == 0; }

  // The first cycle at or after `from` whose bucket is marked in `nonempty` (a bit per bucket of
  // a wheel of kWheelCycles), all ones when none is; every marked bucket's cycle lies in
  // [from, from + kWheelCycles). Shared with UnitQueue, which keeps the same bitmap.
  static uint64_t first_marked_cycle(const std::vector<uint64_t>& nonempty, uint64_t from) {
    constexpr uint64_t kWords = kWheelCycles / 64;
    uint64_t c = from;
    for (uint64_t i = 0; i <= kWords; ++i) {
      const uint64_t b = c & (kWheelCycles - 1);
      const uint64_t bits = nonempty[b / 64] & (~uint64_t{0} << (b % 64));
      if (bits) return c - (b % 64) + static_cast<uint64_t>(std::countr_zero(bits));
      c += 64 - (b % 64);
    }
    return ~uint64_t{0};
  }

  // push, top_cycle and pop are forced inline: one of each per unit event, in its hot loop.
  // Schedules `slot` at `cycle` (>= the cycle of the last pop).
  [[gnu::always_inline]] void push(uint64_t cycle, uint32_t slot) {
    ++count_;
    if (next_ != kUnknown) next_ = std::min(next_, cycle);  // else found at the next peek
    if (cycle >= now_ + kWheelCycles) {
      far_.push(cycle << kSlotBits | slot);  // slots < 2^kSlotBits
      return;
    }
    const uint64_t b = cycle & (kWheelCycles - 1);
    link_[slot] = kNone;
    if (head_[b] == kNone) {
      head_[b] = slot;
      nonempty_[b / 64] |= uint64_t{1} << (b % 64);
      tail_[b] = slot;
    } else if (!slot_order_ || tail_[b] < slot) {
      link_[tail_[b]] = slot;
      tail_[b] = slot;
    } else if (slot < head_[b]) {
      link_[slot] = head_[b];
      head_[b] = slot;
    } else {  // between two entries
      uint32_t prev = head_[b];
      while (link_[prev] < slot) prev = link_[prev];
      link_[slot] = link_[prev];
      link_[prev] = slot;
    }
  }

  // Cycle of the next event (the queue must not be empty).
  [[gnu::always_inline]] uint64_t top_cycle() {
    if (next_ == kUnknown) {
      const uint64_t far = far_.empty() ? ~uint64_t{0} : far_.top() >> kSlotBits;
      next_ = std::min(next_wheel_cycle(), far);
    }
    return next_;
  }

  // Takes the next event: its slot; `cycle` receives its cycle.
  [[gnu::always_inline]] uint32_t pop(uint64_t& cycle) {
    --count_;
    const uint64_t wheel = top_cycle();
    next_ = kUnknown;
    if (!far_.empty() && (far_.top() >> kSlotBits) <= wheel) {
      const uint64_t key = far_.top();
      far_.pop();
      cycle = key >> kSlotBits;
      now_ = cycle;
      return static_cast<uint32_t>(key & ((uint64_t{1} << kSlotBits) - 1));
    }
    const uint64_t b = wheel & (kWheelCycles - 1);
    const uint32_t slot = head_[b];
    head_[b] = link_[slot];
    if (head_[b] == kNone)
      nonempty_[b / 64] &= ~(uint64_t{1} << (b % 64));
    else  // more this cycle (a far event of it would have come first: none is left)
      next_ = wheel;
    cycle = wheel;
    now_ = wheel;
    return slot;
  }

 private:
  // First non-empty bucket from now_, as a cycle (all wheel events are in [now_, now_ + W)).
  uint64_t next_wheel_cycle() const { return first_marked_cycle(nonempty_, now_); }

  bool slot_order_;
  std::vector<uint32_t> link_;  // per slot: the next slot in its bucket
  std::vector<uint32_t> head_, tail_;
  std::vector<uint64_t> nonempty_;
  std::priority_queue<uint64_t, std::vector<uint64_t>, std::greater<uint64_t>> far_;
  static constexpr uint64_t kUnknown = ~uint64_t{0};
  uint64_t now_ = 0;
  uint64_t count_ = 0;
  uint64_t next_ = kUnknown;  // cycle of the next event, when known
};

}  // namespace rtusim
