// The LRU stack of a fully associative cache, cut into regions at several capacities: one pass
// tells, for every capacity at once, whether an access hits. The stack is a doubly linked list
// over dense line numbers; a marker sits at each capacity boundary, and moving a line to the top
// shifts the last line of every region above the line's old place one region down, so an access
// costs O(number of capacities), whatever the capacities are (Mattson's stack with markers,
// instead of a search down a stack thousands of lines deep).
#pragma once
#include <cstdint>
#include <vector>

namespace rtusim {

class FullyAssocLruStack {
 public:
  // `capacities_lines`: strictly increasing; `lines`: line numbers are below it.
  FullyAssocLruStack(std::vector<uint64_t> capacities_lines, uint64_t lines);

  // Accesses `line`; returns the region it was in: r < regions() means a hit in every cache of
  // capacity index >= r, and regions() a miss in all.
  uint32_t access(uint32_t line) {
    if (node_[sentinel_].next == line) return 0;  // already the most recent
    const uint32_t r = node_[line].region;
    if (r < regions_) {
      --count_[r];
      if (tail_[r] == line) tail_[r] = node_[line].prev;
      unlink(line);
    }
    link_front(line);
    node_[line].region = 0;
    if (++count_[0] == 1) tail_[0] = line;
    // Each region that now holds one line too many hands its last line to the next region.
    for (uint32_t j = 0; j < regions_ && count_[j] > capacity_[j]; ++j) {
      const uint32_t t = tail_[j];
      tail_[j] = node_[t].prev;
      --count_[j];
      if (j + 1 == regions_) {
        unlink(t);
        node_[t].region = regions_;
      } else {
        node_[t].region = j + 1;
        if (++count_[j + 1] == 1) tail_[j + 1] = t;
      }
    }
    return r;
  }

  // Hints that `line` comes soon (its node is fetched into the cache).
  void prefetch(uint32_t line) const { __builtin_prefetch(&node_[line]); }

  uint32_t regions() const { return regions_; }

 private:
  // A line's links and region in one 16-byte block: an access touches one memory line per line.
  struct Node {
    uint32_t prev = 0, next = 0, region = 0, unused = 0;
  };

  void unlink(uint32_t x) {
    node_[node_[x].prev].next = node_[x].next;
    node_[node_[x].next].prev = node_[x].prev;
  }
  void link_front(uint32_t x) {
    node_[x].prev = sentinel_;
    node_[x].next = node_[sentinel_].next;
    node_[node_[sentinel_].next].prev = x;
    node_[sentinel_].next = x;
  }

  uint32_t regions_;
  uint32_t sentinel_;               // list head/tail node, index `lines`
  std::vector<uint64_t> capacity_;  // lines in region j (capacity j minus capacity j-1)
  std::vector<uint64_t> count_;     // lines now in region j
  std::vector<uint32_t> tail_;      // last (least recent) line of region j
  std::vector<Node> node_;          // per line; region regions_ = not in the stack
};

}  // namespace rtusim
