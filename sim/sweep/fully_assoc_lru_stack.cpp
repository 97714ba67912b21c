#include "sweep/fully_assoc_lru_stack.h"

#include <stdexcept>

namespace rtusim {

FullyAssocLruStack::FullyAssocLruStack(std::vector<uint64_t> capacities_lines, uint64_t lines)
    : regions_(static_cast<uint32_t>(capacities_lines.size())),
      sentinel_(static_cast<uint32_t>(lines)),
      count_(capacities_lines.size(), 0),
      tail_(capacities_lines.size(), 0),
      prev_(lines + 1),
      next_(lines + 1),
      region_(lines + 1, static_cast<uint32_t>(capacities_lines.size())) {
  if (lines >= UINT32_MAX) throw std::logic_error("FullyAssocLruStack: too many lines");
  uint64_t below = 0;
  for (const uint64_t c : capacities_lines) {
    if (c <= below) throw std::logic_error("FullyAssocLruStack: capacities must increase");
    capacity_.push_back(c - below);
    below = c;
  }
  prev_[sentinel_] = next_[sentinel_] = sentinel_;
}

}  // namespace rtusim
