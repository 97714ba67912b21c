#include "sweep/fully_assoc_lru_stack.h"

#include <algorithm>
#include <stdexcept>

namespace rtusim {

FullyAssocLruStack::FullyAssocLruStack(std::vector<uint64_t> capacities_lines, uint64_t lines)
    : regions_(static_cast<uint32_t>(capacities_lines.size())),
      count_(capacities_lines.size(), 0),
      tail_(capacities_lines.size(), 0),
      slot_(lines, kNone) {
  if (lines >= UINT32_MAX) throw std::logic_error("FullyAssocLruStack: too many lines");
  uint64_t below = 0;
  for (const uint64_t c : capacities_lines) {
    if (c <= below) throw std::logic_error("FullyAssocLruStack: capacities must increase");
    capacity_.push_back(c - below);
    below = c;
  }
  // The largest capacity's lines, and one more while an access makes room.
  const uint64_t slots = std::min<uint64_t>(below, lines) + 1;
  sentinel_ = static_cast<uint32_t>(slots);
  node_.assign(slots + 1, Node{});
  node_[sentinel_].prev = node_[sentinel_].next = sentinel_;
  for (uint64_t x = slots; x-- > 0;) free_.push_back(static_cast<uint32_t>(x));
}

}  // namespace rtusim
