// The timed interleaved mode's event queue for up to 64 x kWords ray slots: the events of
// SlotEventTree in the same order (the earliest first; among events of one cycle those set
// kFarCycles or more after the last event taken go first, then by slot), at a lower cost per
// event. A timing wheel of one bucket per cycle over the next kFarCycles: a bucket is a bit mask
// of its slots (the lowest bit is the next) and a bitmap marks the non-empty buckets, so the next
// event is two bit scans away. An event set kFarCycles or more ahead (a far one) waits in a small
// heap instead.
// For the mode's pattern: take() removes the event it returns, and the slot is then set again
// or cleared (a no-op: a slot without an event has nothing to remove).
#pragma once
#include <bit>
#include <cstdint>
#include <functional>
#include <queue>
#include <stdexcept>
#include <vector>

#include "tier/slot_event_tree.h"

namespace rtusim {

template <int kWords>
class SlotEventWheel {
 public:
  static constexpr uint64_t kFarCycles = SlotEventTree::kFarCycles;
  static constexpr uint32_t kMaxSlots = 64 * kWords;
  static constexpr uint64_t kNoCycle = ~uint64_t{0};

  explicit SlotEventWheel(uint32_t slots) {
    if (slots > kMaxSlots) throw std::logic_error("slot event wheel: too many slots");
  }

  // Takes and removes the next event: false when there is none, else its slot and cycle.
  [[gnu::always_inline]] bool take(uint32_t& slot, uint64_t& cycle) {
    return take(slot, cycle, kNoCycle);
  }
  // take() of an event of cycle `limit` or earlier: false (nothing removed) when there is none.
  [[gnu::always_inline]] bool take(uint32_t& slot, uint64_t& cycle, uint64_t limit) {
    // The first non-empty bucket from now_ on (the wheel's events lie in [now_, now_ + W)).
    const uint64_t b0 = now_ & kBucketMask;
    uint64_t w = b0 / 64;
    uint64_t word = nonempty_[w];
    uint64_t bits = word & (~uint64_t{0} << (b0 % 64));
    uint64_t wheel = kNoCycle;
    if (!bits) [[unlikely]] {
      // The next non-empty word, wrapping round (w's low bits, the latest cycles, come last).
      for (uint64_t i = 1; i <= kMarkWords && !bits; ++i)
        bits = word = nonempty_[w = (b0 / 64 + i) % kMarkWords];
    }
    const uint64_t b = w * 64 + static_cast<uint64_t>(std::countr_zero(bits));
    if (bits) wheel = now_ + ((b - b0) & kBucketMask);
    if (far_next_ <= wheel) [[unlikely]] {  // a far event of that cycle or earlier goes first
      if (far_next_ == kNoCycle || far_next_ > limit) return false;
      const uint64_t key = far_.top();
      far_.pop();
      far_next_ = far_.empty() ? kNoCycle : far_.top() >> kSlotBits;
      cycle = now_ = key >> kSlotBits;
      slot = static_cast<uint32_t>(key & ((uint64_t{1} << kSlotBits) - 1));
      return true;
    }
    if (wheel > limit) return false;
    uint64_t* m = &masks_[b * kWords];
    int i = 0;
    if constexpr (kWords > 1)
      while (m[i] == 0) ++i;
    slot = static_cast<uint32_t>(64 * i + std::countr_zero(m[i]));
    m[i] &= m[i] - 1;
    bool bucket_empty = m[i] == 0;
    if constexpr (kWords > 1)
      for (int j = 0; j < kWords; ++j) bucket_empty &= m[j] == 0;
    // Without a branch: whether a bucket holds one slot or more is not predictable.
    nonempty_[w] = word & ~(uint64_t{bucket_empty} << (b % 64));
    cycle = now_ = wheel;
    return true;
  }

  // Schedules `slot` (without an event) at `cycle`, no earlier than the last event taken.
  [[gnu::always_inline]] void set(uint32_t slot, uint64_t cycle) {
    if (cycle - now_ >= kFarCycles) [[unlikely]] {
      if (cycle >> (63 - kSlotBits)) throw std::logic_error("slot event wheel: cycle out of range");
      far_.push(cycle << kSlotBits | slot);
      far_next_ = far_.top() >> kSlotBits;
      return;
    }
    const uint64_t b = cycle & kBucketMask;
    masks_[b * kWords + slot / 64] |= uint64_t{1} << (slot % 64);
    nonempty_[b / 64] |= uint64_t{1} << (b % 64);
  }
  // `slot` has no event (it was taken): nothing to remove.
  void clear(uint32_t /*slot*/) {}

 private:
  static constexpr int kSlotBits = 16;  // a far event's key is cycle << kSlotBits | slot
  static constexpr uint64_t kBucketMask = kFarCycles - 1;
  static constexpr uint64_t kMarkWords = kFarCycles / 64;  // of nonempty_
  static_assert(kFarCycles % 64 == 0);

  uint64_t now_ = 0;                  // the cycle of the last event taken
  uint64_t far_next_ = kNoCycle;      // the earliest far event's cycle
  uint64_t nonempty_[kMarkWords] = {};     // bit b % 64 of word b / 64: bucket b holds a slot
  uint64_t masks_[kFarCycles * kWords] = {};    // [bucket * kWords + slot / 64]: bit slot % 64
  std::priority_queue<uint64_t, std::vector<uint64_t>, std::greater<uint64_t>> far_;
};

}  // namespace rtusim
