// The timed interleaved mode's event queue: at most one event per ray slot, the earliest first,
// in EventWheel's order (the queue the mode used first, whose order its figures keep): among
// events of one cycle those set kFarCycles or more after the last event taken (the wheel's far
// events) go first, then by slot. A tournament tree over the slots: each inner node holds the
// smaller key of its two children, so the next event is the root, and setting a slot's event
// recomputes its path to the root (log2 slots minimums of loads that do not wait on each other). The mode's
// pattern, take the next event and then set that slot's next, costs no heap sift and no search.
#pragma once
#include <algorithm>
#include <bit>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "model/event_wheel.h"

namespace rtusim {

class SlotEventTree {
 public:
  static constexpr int kSlotBits = 16;  // a key is cycle << (kSlotBits + 1) | near | slot
  static constexpr uint64_t kNone = ~uint64_t{0};
  static constexpr uint64_t kFarCycles = EventWheel::kWheelCycles;

  explicit SlotEventTree(uint32_t slots)
      : leaves_(std::bit_ceil(std::max<uint32_t>(slots, 2))), key_(2 * leaves_, kNone) {
    if (slots > (1u << kSlotBits)) throw std::logic_error("slot event tree: too many slots");
  }

  bool empty() const { return key_[1] == kNone; }
  // Takes the next event (the tree must not be empty): its slot; `cycle` receives its cycle.
  // It stays in the tree until its slot is set or cleared.
  uint32_t take(uint64_t& cycle) {
    cycle = now_ = key_[1] >> (kSlotBits + 1);
    return static_cast<uint32_t>(key_[1] & kSlotMask);
  }

  // Schedules `slot` at `cycle` (no earlier than the last event taken), replacing its event.
  [[gnu::always_inline]] void set(uint32_t slot, uint64_t cycle) {
    if (cycle >> (63 - kSlotBits)) [[unlikely]]
      throw std::logic_error("slot event tree: cycle out of range");
    const uint64_t near = cycle < now_ + kFarCycles;
    update(slot, cycle << (kSlotBits + 1) | near << kSlotBits | slot);
  }
  // Removes `slot`'s event.
  void clear(uint32_t slot) { update(slot, kNone); }

 private:
  static constexpr uint64_t kSlotMask = (uint64_t{1} << kSlotBits) - 1;
  // Sets `slot`'s leaf to `key`, then each node on its path to the root to its children's minimum.
  [[gnu::always_inline]] void update(uint32_t slot, uint64_t key) {
    size_t i = leaves_ + slot;
    key_[i] = key;
    for (; i > 1; i >>= 1) {
      key = std::min(key, key_[i ^ 1]);
      key_[i >> 1] = key;
    }
  }

  uint64_t now_ = 0;           // the cycle of the last event taken
  size_t leaves_;              // a power of two >= the slots
  std::vector<uint64_t> key_;  // [1] the root; [leaves_ + slot] a slot's event; kNone: none
};

}  // namespace rtusim
