// The traversal unit's one queue of what happens next: arrivals (a ray whose data is all there)
// and events (a ray's next pipeline action), at most one of either per ray slot, each at a cycle
// no earlier than the last one taken. It gives them by cycle; within a cycle the arrivals
// first, in slot order (wherever each is kept), then the events, in push order (an event kept in
// the far heap, pushed kWheelCycles or more ahead of the last event taken, was pushed before any
// of its cycle in the wheel; far ones by slot).
// One timing wheel of a bucket per cycle over the next kWheelCycles (per bucket a slot-sorted
// list of arrivals and a FIFO list of events, threaded through the slots; one bitmap of
// non-empty buckets), plus a heap per kind for the rare entry further ahead: one scan finds the
// next cycle of both kinds.
#pragma once
#include <algorithm>
#include <bit>
#include <cstdint>
#include <functional>
#include <queue>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/event_wheel.h"
#include "util/error.h"

namespace rtusim {

class UnitQueue {
 public:
  static constexpr uint64_t kWheelCycles = EventWheel::kWheelCycles;
  static constexpr uint32_t kNone = ~uint32_t{0};
  static constexpr uint32_t kSlotBits = EventWheel::kSlotBits;  // far: cycle << 20 | slot
  static constexpr uint64_t kSlotMask = (uint64_t{1} << kSlotBits) - 1;

  explicit UnitQueue(uint32_t slots)
      : link_arrival_(slots, kNone), link_event_(slots, kNone),
        buckets_(kWheelCycles), nonempty_(kWheelCycles / 64, 0) {}

  bool empty() const { return next_ == kEmpty; }

  // push_*, top_cycle and pop are forced inline: one of each per unit event, in its hot loop.
  // Schedules slot's arrival at `cycle` (>= the cycle of the last pop; kChecked false: the
  // caller knows it is, and it is not tested).
  template <bool kChecked = true>
  [[gnu::always_inline]] void push_arrival(uint64_t cycle, uint32_t slot) {
    before_push<kChecked>(cycle);
    if (cycle >= now_arrival_ + kWheelCycles) [[unlikely]] {
      push_far(far_arrival_, cycle, slot);
      return;
    }
    const uint64_t b = cycle & (kWheelCycles - 1);
    Bucket& k = buckets_[b];
    link_arrival_[slot] = kNone;
    if (k.arrival_head == kNone) {
      k.arrival_head = slot;
      k.arrival_tail = slot;
      mark(b);
    } else if (k.arrival_tail < slot) {
      link_arrival_[k.arrival_tail] = slot;
      k.arrival_tail = slot;
    } else if (slot < k.arrival_head) {
      link_arrival_[slot] = k.arrival_head;
      k.arrival_head = slot;
    } else {  // between two entries
      uint32_t prev = k.arrival_head;
      while (link_arrival_[prev] < slot) prev = link_arrival_[prev];
      link_arrival_[slot] = link_arrival_[prev];
      link_arrival_[prev] = slot;
    }
  }

  // Schedules slot's event at `cycle` (>= the cycle of the last pop; kChecked: as above).
  template <bool kChecked = true>
  [[gnu::always_inline]] void push_event(uint64_t cycle, uint32_t slot) {
    before_push<kChecked>(cycle);
    if (cycle >= now_event_ + kWheelCycles) [[unlikely]] {
      push_far(far_event_, cycle, slot);
      return;
    }
    const uint64_t b = cycle & (kWheelCycles - 1);
    Bucket& k = buckets_[b];
    link_event_[slot] = kNone;
    if (k.event_head == kNone) {
      k.event_head = slot;
      mark(b);
    } else {
      link_event_[k.event_tail] = slot;
    }
    k.event_tail = slot;
  }

  // Cycle of the next entry; all ones when the queue is empty.
  [[gnu::always_inline]] uint64_t top_cycle() const { return next_; }

  // Takes the next entry: its slot; `cycle` receives its cycle, `arrival` its kind.
  [[gnu::always_inline]] uint32_t pop(uint64_t& cycle, bool& arrival) {
    const uint64_t c = next_;
    cycle = c;
    now_ = c;
    const uint64_t b = c & (kWheelCycles - 1);
    Bucket& k = buckets_[b];
    uint32_t slot;
    // A far entry of this cycle (rare): the far heaps' tops are checked. A far arrival goes
    // first only if its slot is below the wheel's first arrival of the cycle: arrivals of a
    // cycle are taken in slot order, however far ahead each was pushed.
    if (far_next_ == c && !far_arrival_.empty() && (far_arrival_.top() >> kSlotBits) == c &&
        (k.arrival_head == kNone || static_cast<uint32_t>(far_arrival_.top() & kSlotMask) <
                                        k.arrival_head)) [[unlikely]] {
      slot = take_far(far_arrival_);
      arrival = true;
      now_arrival_ = c;
      next_ = find_next();
      return slot;
    }
    if (k.arrival_head != kNone) {
      slot = k.arrival_head;
      k.arrival_head = link_arrival_[slot];
      arrival = true;
      now_arrival_ = c;
    } else {
      if (far_next_ == c && !far_event_.empty() && (far_event_.top() >> kSlotBits) == c)
          [[unlikely]] {
        slot = take_far(far_event_);
        arrival = false;
        now_event_ = c;
        next_ = find_next();
        return slot;
      }
      slot = k.event_head;
      k.event_head = link_event_[slot];
      arrival = false;
      now_event_ = c;
    }
    if (k.arrival_head == kNone && k.event_head == kNone) {
      uint64_t& word = nonempty_[b / 64];
      word &= ~(uint64_t{1} << (b % 64));
      // The next marked bucket of this word if any (the common case), else the scan; a far
      // entry of this cycle, if any, included.
      const uint64_t later = word & (~uint64_t{0} << (b % 64));
      next_ = later ? std::min(c - b % 64 + static_cast<uint64_t>(std::countr_zero(later)),
                               far_next_)
                    : find_next();
    } else {
      next_ = c;
    }
    return slot;
  }

 private:
  struct Bucket {
    uint32_t arrival_head = kNone, arrival_tail = kNone;
    uint32_t event_head = kNone, event_tail = kNone;
  };
  using FarHeap = std::priority_queue<uint64_t, std::vector<uint64_t>, std::greater<uint64_t>>;

  template <bool kChecked>
  [[gnu::always_inline]] void before_push(uint64_t cycle) {
    // Every wheel entry must lie in [now_, now_ + kWheelCycles) for the buckets to order them.
    if (kChecked && cycle < now_) [[unlikely]] behind(cycle);
    next_ = std::min(next_, cycle);
  }
  [[noreturn, gnu::cold]] void behind(uint64_t cycle) const {
    throw std::logic_error("traversal unit: an entry at cycle " + std::to_string(cycle) +
                           " behind the last one taken, " + std::to_string(now_));
  }
  [[gnu::always_inline]] void mark(uint64_t b) { nonempty_[b / 64] |= uint64_t{1} << (b % 64); }
  // An entry kWheelCycles or more ahead of the last of its kind taken (rare; out of line, so
  // the inline pushes need no heap code).
  [[gnu::noinline, gnu::cold]] void push_far(FarHeap& far, uint64_t cycle, uint32_t slot) {
    // A far entry keeps its cycle in the key's top 44 bits: past that, a clear error, not a
    // corrupted cycle (it crashed the run).
    if (cycle >> (64 - kSlotBits))
      throw InputError("the simulated time reached 2^44 cycles (" + std::to_string(cycle) +
                       "), the traversal unit's limit: simulate a smaller frame or shorter "
                       "latencies (isect.*, unit.*, dram.*)");
    far.push(cycle << kSlotBits | slot);
    far_next_ = std::min(far_next_, cycle);
  }
  uint32_t take_far(FarHeap& far) {
    const uint64_t key = far.top();
    far.pop();
    far_next_ = kEmpty;
    if (!far_arrival_.empty()) far_next_ = far_arrival_.top() >> kSlotBits;
    if (!far_event_.empty()) far_next_ = std::min(far_next_, far_event_.top() >> kSlotBits);
    return static_cast<uint32_t>(key & kSlotMask);
  }
  // The cycle of the next entry, the wheel's or a far one (all ones: none).
  uint64_t find_next() const {
    return std::min(next_wheel_cycle(), far_next_);
  }
  // First non-empty bucket from now_, as a cycle (all wheel entries are in [now_, now_ + W):
  // each kind's last cycle taken is at or before now_).
  uint64_t next_wheel_cycle() const { return EventWheel::first_marked_cycle(nonempty_, now_); }

  std::vector<uint32_t> link_arrival_, link_event_;  // per slot: the next slot in its bucket
  std::vector<Bucket> buckets_;
  std::vector<uint64_t> nonempty_;
  FarHeap far_arrival_, far_event_;
  uint64_t far_next_ = kEmpty;  // the earliest cycle in either far heap (all ones: none)
  static constexpr uint64_t kEmpty = ~uint64_t{0};
  uint64_t now_ = 0;                             // cycle of the last entry taken
  uint64_t now_arrival_ = 0, now_event_ = 0;     // of the last of each kind taken
  uint64_t next_ = kEmpty;  // cycle of the next entry, kept at every push and pop
};

}  // namespace rtusim
