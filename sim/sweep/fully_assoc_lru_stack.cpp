#include "sweep/fully_assoc_lru_stack.h"

#include <algorithm>
#include <stdexcept>

namespace rtusim {

FullyAssocLruStack::FullyAssocLruStack(std::vector<uint64_t> capacities_lines, uint64_t lines)
    : regions_(static_cast<uint32_t>(capacities_lines.size())) {
  if (lines >= UINT32_MAX) throw std::logic_error("FullyAssocLruStack: too many lines");
  if (capacities_lines.empty()) throw std::logic_error("FullyAssocLruStack: no capacity");
  for (size_t r = 0; r < capacities_lines.size(); ++r)
    if (capacities_lines[r] == 0 || (r > 0 && capacities_lines[r] <= capacities_lines[r - 1]))
      throw std::logic_error("FullyAssocLruStack: capacities must increase");
  const uint64_t largest = capacities_lines.back();
  top_lines_ = static_cast<uint32_t>(std::min<uint64_t>(kTop, largest));
  std::fill(std::begin(top_), std::end(top_), kNone);
  // The array's positions by region; the list's parts between the boundaries below it.
  for (uint32_t p = 0, r = 0; p < top_lines_; ++p) {
    while (p >= capacities_lines[r]) ++r;
    region_of_top_.push_back(r);
  }
  first_list_region_ = static_cast<uint32_t>(
      std::upper_bound(capacities_lines.begin(), capacities_lines.end(), uint64_t{top_lines_}) -
      capacities_lines.begin());
  uint64_t below = top_lines_;
  for (uint32_t r = first_list_region_; r < regions_; ++r) {
    capacity_.push_back(capacities_lines[r] - below);
    below = capacities_lines[r];
  }
  list_regions_ = static_cast<uint32_t>(capacity_.size());
  if (list_regions_ == 0) return;
  count_.assign(list_regions_, 0);
  tail_.assign(list_regions_, 0);
  slot_.assign(lines, kNone);
  // The list's part of the largest capacity, and one more slot while an access makes room.
  const uint64_t held = std::min(largest, lines);
  const uint64_t slots = (held > top_lines_ ? held - top_lines_ : 0) + 1;
  sentinel_ = static_cast<uint32_t>(slots);
  node_.assign(slots + 1, Node{});
  node_[sentinel_].prev = node_[sentinel_].next = sentinel_;
  for (uint64_t x = slots; x-- > 0;) free_.push_back(static_cast<uint32_t>(x));
}

}  // namespace rtusim
