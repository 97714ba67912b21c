// Tree pseudo-LRU (the classic binary-tree PLRU of many L1 caches), for a power-of-two number
// of ways W = 2^k. Exact definition, so an RTL version can follow it bit for bit:
//
//  - Each set keeps W - 1 bits, one per internal node of a complete binary tree whose leaves are
//    the ways 0 .. W-1 from left to right. Nodes are numbered heap style: the root is 1, the
//    children of node n are 2n (left) and 2n + 1 (right), and way w is leaf W + w. So at depth d
//    (root d = 0) the path to way w goes right iff bit (k - 1 - d) of w is 1.
//  - Bit b[n] points at the older (less recently used) half below node n:
//    0 = the left subtree is older, 1 = the right subtree is older.
//  - Touch of way w (on a hit and on a fill): walk from the root to leaf W + w and set every bit
//    on the path to point away from the path: b[n] = 1 where the path goes left, 0 where it goes
//    right.
//  - Victim: start at the root and follow the bits (0 -> left child, 1 -> right child) down to a
//    leaf; its way is the victim. Choosing a victim changes no bit (the fill's touch does).
//  - Reset: all bits 0 (the victim would be way 0); invalid ways are filled first, lowest first.
//
// Example, 4 ways (b1 = root, b2 over ways 0/1, b3 over ways 2/3), fills of ways 0, 1, 2, 3:
// b1 b2 b3 = 0 0 0; the victim is way 0; after refilling way 0 (b1 = 1, b2 = 1) it is way 2,
// whereas true LRU would evict way 1.
#pragma once
#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include "cache/replacement_policy.h"
#include "util/error.h"

namespace rtusim {

class TreePlruPolicy final : public ReplacementPolicy {
 public:
  static constexpr const char* kName = "tree-plru";
  // What rules out `ways` ways ("": nothing): the tree needs a power of two.
  static std::string ways_problem(uint32_t ways) {
    return std::has_single_bit(ways) ? "" : "must be a power of two";
  }
  TreePlruPolicy(uint32_t sets, uint32_t ways, uint64_t /*seed*/)
      : ways_(ways), levels_(static_cast<uint32_t>(std::countr_zero(ways))),
        bits_(uint64_t{sets} * ways, 0) {
    if (const std::string why = ways_problem(ways); !why.empty())
      throw InputError("tree_plru: the associativity (" + std::to_string(ways) + ") " + why);
  }

  const char* name() const override { return kName; }
  bool retouch_neutral() const override { return true; }  // its path already points away from it
  void touch(uint32_t set, uint32_t way) override {
    uint8_t* b = &bits_[uint64_t{set} * ways_];  // b[1 .. W-1]; b[0] unused
    uint32_t node = 1;
    for (uint32_t level = levels_; level-- > 0;) {
      const uint32_t right = (way >> level) & 1u;
      b[node] = static_cast<uint8_t>(right ^ 1u);  // point at the other half
      node = 2 * node + right;
    }
  }
  void fill(uint32_t set, uint32_t way) override { touch(set, way); }
  uint32_t victim(uint32_t set) override {
    const uint8_t* b = &bits_[uint64_t{set} * ways_];
    uint32_t node = 1;
    while (node < ways_) node = 2 * node + b[node];
    return node - ways_;
  }

 private:
  uint32_t ways_;
  uint32_t levels_;            // k = log2(ways)
  std::vector<uint8_t> bits_;  // [set * ways + node], node in 1 .. ways-1
};

}  // namespace rtusim
