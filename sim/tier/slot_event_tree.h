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
      : leaves_(std::bit_ceil(std::max<uint32_t>(slots, 2))),
        levels_(std::countr_zero(leaves_)), key_(2 * leaves_, kNone) {
    if (slots > (1u << kSlotBits)) throw std::logic_error("slot event tree: too many slots");
  }

  bool empty() const { return key_[1] == kNone; }
  // Takes the next event (the tree must not be empty): its slot; `cycle` receives its cycle.
  // It stays in the tree until its slot is set or cleared.
  uint32_t take(uint64_t& cycle) {
    cycle = now_ = key_[1] >> (kSlotBits + 1);
    return static_cast<uint32_t>(key_[1] & kSlotMask);
  }

  // take() when the tree is not empty: false when it is.
  bool take(uint32_t& slot, uint64_t& cycle) {
    if (empty()) return false;
    slot = take(cycle);
    return true;
  }

  // take() of an event of cycle `limit` or earlier: false when there is none.
  bool take(uint32_t& slot, uint64_t& cycle, uint64_t limit) {
    if (empty() || key_[1] >> (kSlotBits + 1) > limit) return false;
    slot = take(cycle);
    return true;
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
  // The climb is unrolled: entered at the tree's height, one level a case, falling through.
  [[gnu::always_inline]] void update(uint32_t slot, uint64_t key) {
    uint64_t* const k = key_.data();
    size_t i = leaves_ + slot;
    k[i] = key;
    auto up = [&]() __attribute__((always_inline)) {
      key = std::min(key, k[i ^ 1]);
      i >>= 1;
      k[i] = key;
    };
    static_assert(kSlotBits == 16, "one case per level");
    switch (levels_) {
      case 16: up(); [[fallthrough]];
      case 15: up(); [[fallthrough]];
      case 14: up(); [[fallthrough]];
      case 13: up(); [[fallthrough]];
      case 12: up(); [[fallthrough]];
      case 11: up(); [[fallthrough]];
      case 10: up(); [[fallthrough]];
      case 9: up(); [[fallthrough]];
      case 8: up(); [[fallthrough]];
      case 7: up(); [[fallthrough]];
      case 6: up(); [[fallthrough]];
      case 5: up(); [[fallthrough]];
      case 4: up(); [[fallthrough]];
      case 3: up(); [[fallthrough]];
      case 2: up(); [[fallthrough]];
      default: up();
    }
  }

  uint64_t now_ = 0;           // the cycle of the last event taken
  size_t leaves_;              // a power of two >= the slots (>= 2)
  int levels_;                 // log2 leaves_: the levels above the leaves (1 to kSlotBits)
  std::vector<uint64_t> key_;  // [1] the root; [leaves_ + slot] a slot's event; kNone: none
};

}  // namespace rtusim
