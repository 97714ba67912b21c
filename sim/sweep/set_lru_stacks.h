// LRU stack distances within the sets of one set count (Mattson et al. 1970, per set as in Hill &
// Smith 1989): one pass gives the hits of every associativity up to `depth` at this set count.
// A line at distance d (0 = most recent in its set) hits in every LRU cache of this set count
// with more than d ways; the cache fills invalid ways first, which LRU treats as oldest, so the
// inclusion property holds exactly.
#pragma once
#include <cstdint>
#include <vector>

namespace rtusim {

class SetLruStacks {
 public:
  SetLruStacks(uint32_t sets, uint32_t depth);

  // Accesses `line`; returns its stack distance in its set before the access, or depth() when it
  // was deeper (or never seen). The line becomes the most recent of its set.
  uint32_t access(uint64_t line) {
    const auto tag = static_cast<uint32_t>(line);
    uint32_t* s = &stacks_[(line & set_mask_) * depth_];
    uint32_t d = 0;
    while (d < depth_ && s[d] != tag) ++d;
    const uint32_t moved = d < depth_ ? d : depth_ - 1;
    for (uint32_t i = moved; i > 0; --i) s[i] = s[i - 1];
    s[0] = tag;
    return d;
  }

  uint32_t sets() const { return static_cast<uint32_t>(set_mask_ + 1); }
  uint32_t depth() const { return depth_; }

 private:
  static constexpr uint32_t kEmpty = ~uint32_t{0};  // never a line number (lines < 2^32 - 1)
  uint64_t set_mask_;
  uint32_t depth_;
  std::vector<uint32_t> stacks_;  // [set * depth + distance]: line numbers, most recent first
};

}  // namespace rtusim
