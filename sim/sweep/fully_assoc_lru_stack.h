// The LRU stack of a fully associative cache, cut into regions at several capacities: one pass
// tells, for every capacity at once, whether an access hits. The most recent lines (up to kTop)
// sit in a small array, most recent first, searched with one compare per 16 lines and shifted
// with a masked move (most accesses end there: no table look-up, no list). Below it, the lines
// within the largest capacity form a doubly linked list; a marker sits at each capacity
// boundary, and moving a line to the top shifts the last line of every region above the line's
// old place one region down, so a deeper access costs O(number of capacities), whatever the
// capacities are (Mattson's stack with markers, instead of a search down a stack thousands of
// lines deep). The list's lines take slots of a pool (its links stay in a small, hot array); a
// per-line table finds a listed line's slot.
#pragma once
#include <cstdint>
#include <vector>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace rtusim {

class FullyAssocLruStack {
 public:
  static constexpr uint32_t kTop = 32;  // most lines held in the array (a multiple of 16)

  // `capacities_lines`: strictly increasing; `lines`: line numbers are below it (and below
  // 2^32 - 1).
  FullyAssocLruStack(std::vector<uint64_t> capacities_lines, uint64_t lines);

  // Accesses `line`; returns the region it was in: r < regions() means a hit in every cache of
  // capacity index >= r, and regions() a miss in all.
  uint32_t access(uint32_t line) {
    const uint32_t p = top_find(line);
    if (p < top_lines_) {
      top_push(line, p);
      return region_of_top_[p];
    }
    // Deeper than the array: its last line goes down to the head of the list, where the line
    // accessed (if listed) leaves.
    const uint32_t dropped = top_[top_lines_ - 1];
    top_push(line, top_lines_ - 1);
    if (dropped == kNone) return regions_;  // the array was not full yet: nothing below it
    if (list_regions_ == 0) return regions_;  // nothing is held below the array
    uint32_t x = slot_[line];
    uint32_t r = list_regions_;
    if (x == kNone) {  // not listed: the dropped line takes a free slot
      x = free_.back();
      free_.pop_back();
    } else {
      r = node_[x].region;
      --count_[r];
      if (tail_[r] == x) tail_[r] = node_[x].prev;
      unlink(x);
    }
    slot_[dropped] = x;  // the accessed line's entry goes stale: it is read only for listed lines
    node_[x].line = dropped;
    move_to_front(x);
    return r == list_regions_ ? regions_ : first_list_region_ + r;
  }

  // Hints that `line` comes soon (its slot is fetched into the cache).
  void prefetch(uint32_t line) const {
    if (!slot_.empty()) __builtin_prefetch(&slot_[line]);
  }

  uint32_t regions() const { return regions_; }

 private:
  static constexpr uint32_t kNone = ~uint32_t{0};
  // A listed line's links, region and line number in one 16-byte block; the blocks form a pool
  // as large as the list's part of the largest capacity (+1), so the list stays in a hot array.
  struct Node {
    uint32_t prev = 0, next = 0, region = 0, line = 0;
  };

  // The array's position of `line`, or top_lines_ when it is not there.
  uint32_t top_find(uint32_t line) const {
#if defined(__AVX512F__)
    const __m512i key = _mm512_set1_epi32(static_cast<int>(line));
    uint64_t found = 0;
    for (uint32_t v = 0; v < kTop / 16; ++v)
      found |= uint64_t{_mm512_cmpeq_epi32_mask(
                   _mm512_load_si512(reinterpret_cast<const __m512i*>(top_ + 16 * v)), key)}
               << (16 * v);
    return found ? static_cast<uint32_t>(__builtin_ctzll(found)) : top_lines_;
#else
    uint32_t p = 0;
    while (p < top_lines_ && top_[p] != line) ++p;
    return p;
#endif
  }

  // Puts `line` first in the array, the lines at positions 0 .. moved - 1 one place down (the
  // line at `moved` is overwritten: the line itself, or the array's last line).
  void top_push(uint32_t line, uint32_t moved) {
#if defined(__AVX512F__)
    // Lane 0 takes the previous block's last lane (the line, before the first), lane i lane i - 1.
    const __m512i down = _mm512_setr_epi32(15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29, 30);
    __m512i carry = _mm512_set1_epi32(static_cast<int>(line));
    for (uint32_t v = 0; v < kTop / 16; ++v) {
      auto* at = reinterpret_cast<__m512i*>(top_ + 16 * v);
      const __m512i old = _mm512_load_si512(at);
      const uint32_t first = 16 * v;
      if (moved < first) break;
      const uint32_t upto = moved - first;  // lanes 0 .. upto take their upper neighbour
      const auto take = static_cast<__mmask16>(upto >= 15 ? 0xffffu : (2u << upto) - 1);
      _mm512_store_si512(at, _mm512_mask_mov_epi32(old, take, _mm512_permutex2var_epi32(carry, down, old)));
      carry = old;
    }
#else
    for (uint32_t i = moved; i > 0; --i) top_[i] = top_[i - 1];
    top_[0] = line;
#endif
  }

  // Puts slot x at the head of the list (its first region); each region that now holds one line
  // too many hands its last line to the next region, and the last region's overflow leaves.
  void move_to_front(uint32_t x) {
    link_front(x);
    node_[x].region = 0;
    if (++count_[0] == 1) tail_[0] = x;
    for (uint32_t j = 0; j < list_regions_ && count_[j] > capacity_[j]; ++j) {
      const uint32_t t = tail_[j];
      tail_[j] = node_[t].prev;
      --count_[j];
      if (j + 1 == list_regions_) {
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

  alignas(64) uint32_t top_[kTop];   // most recent first; kNone where empty or beyond top_lines_
  uint32_t top_lines_;               // lines the array holds: min(kTop, largest capacity)
  uint32_t regions_;
  std::vector<uint32_t> region_of_top_;  // per array position: its region
  uint32_t first_list_region_ = 0;  // region of the list's first part
  uint32_t list_regions_ = 0;       // parts of the list, between capacity boundaries
  uint32_t sentinel_ = 0;           // list head/tail node, the pool's last slot
  std::vector<uint64_t> capacity_;  // lines in list part j
  std::vector<uint64_t> count_;     // lines now in list part j
  std::vector<uint32_t> tail_;      // last (least recent) slot of list part j
  std::vector<uint32_t> slot_;      // per line: its slot in node_ when listed (else stale/kNone)
  std::vector<Node> node_;          // the pool of slots, then the sentinel
  std::vector<uint32_t> free_;      // slots holding no line
};

}  // namespace rtusim
