#include "sweep/fully_assoc_lru_stack.h"

#include <stdexcept>

namespace rtusim {

FullyAssocLruStack::FullyAssocLruStack(std::vector<uint64_t> capacities_lines, uint64_t lines)
    : regions_(static_cast<uint32_t>(capacities_lines.size())),
      sentinel_(static_cast<uint32_t>(lines)),
      count_(capacities_lines.size(), 0),
      tail_(capacities_lines.size(), 0),
      node_(lines + 1, Node{0, 0, static_cast<uint32_t>(capacities_lines.size()), 0}) {
  if (lines >= UINT32_MAX) throw std::logic_error("FullyAssocLruStack: too many lines");
  uint64_t below = 0;
  for (const uint64_t c : capacities_lines) {
    if (c <= below) throw std::logic_error("FullyAssocLruStack: capacities must increase");
    capacity_.push_back(c - below);
    below = c;
  }
  node_[sentinel_].prev = node_[sentinel_].next = sentinel_;
}

}  // namespace rtusim
