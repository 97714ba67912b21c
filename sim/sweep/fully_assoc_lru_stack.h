// The LRU stack of a fully associative cache, cut into regions at several capacities: one pass
// tells, for every capacity at once, whether an access hits. The stack is a doubly linked list;
// a marker sits at each capacity boundary, and moving a line to the top shifts the last line of
// every region above the line's old place one region down, so an access costs O(number of
// capacities), whatever the capacities are (Mattson's stack with markers, instead of a search
// down a stack thousands of lines deep). Only the lines within the largest capacity are stacked,
// in a pool of slots (its links stay in a small, hot array); a per-line table finds a line's slot.
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
    uint32_t x = slot_[line];
    uint32_t r = regions_;
    if (x == kNone) {  // not in the stack: it takes a free slot
      x = free_.back();
      free_.pop_back();
      slot_[line] = x;
      node_[x].line = line;
    } else {
      if (node_[sentinel_].next == x) return 0;  // already the most recent
      r = node_[x].region;
      --count_[r];
      if (tail_[r] == x) tail_[r] = node_[x].prev;
      unlink(x);
    }
    move_to_front(x);
    return r;
  }

  // Hints that `line` comes soon (its slot is fetched into the cache).
  void prefetch(uint32_t line) const { __builtin_prefetch(&slot_[line]); }

  uint32_t regions() const { return regions_; }

 private:
  static constexpr uint32_t kNone = ~uint32_t{0};
  // A stacked line's links, region and line number in one 16-byte block; the blocks form a pool
  // as large as the largest capacity (+1), so the list's neighbours stay in a small, hot array.
  struct Node {
    uint32_t prev = 0, next = 0, region = 0, line = 0;
  };

  // Puts slot x on top (region 0); each region that now holds one line too many hands its last
  // line to the next region, and the last region's overflow leaves the stack.
  void move_to_front(uint32_t x) {
    link_front(x);
    node_[x].region = 0;
    if (++count_[0] == 1) tail_[0] = x;
    for (uint32_t j = 0; j < regions_ && count_[j] > capacity_[j]; ++j) {
      const uint32_t t = tail_[j];
      tail_[j] = node_[t].prev;
      --count_[j];
      if (j + 1 == regions_) {
        unlink(t);
        slot_[node_[t].line] = kNone;
        free_.push_back(t);
      } else {
        node_[t].region = j + 1;
        if (++count_[j + 1] == 1) tail_[j + 1] = t;
      }
    }
  }

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
  uint32_t sentinel_;               // list head/tail node, the pool's last slot
  std::vector<uint64_t> capacity_;  // lines in region j (capacity j minus capacity j-1)
  std::vector<uint64_t> count_;     // lines now in region j
  std::vector<uint32_t> tail_;      // last (least recent) slot of region j
  std::vector<uint32_t> slot_;      // per line: its slot in node_, kNone when not stacked
  std::vector<Node> node_;          // the pool of slots, then the sentinel
  std::vector<uint32_t> free_;      // slots holding no line
};

}  // namespace rtusim
