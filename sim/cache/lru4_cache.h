// A 4-way true-LRU cache for trace replay. Each set keeps its four tags in recency order, most
// recent first, so a lookup is one compare of the four tags and an update one move of the tags
// before the hit (or of all four on a miss, the last falling out): no per-way time stamps and
// no victim search. On AVX2 hosts the four tags are one vector (compare, permute, blend).
//
// LRU keeps nothing but the recency order, so its hits and misses are those of
// BasicSetAssocCache<LruPolicy> with 4 ways on every access sequence (an empty way holds a tag no
// line has and sinks to the back, so a set fills before it evicts). The ways' positions differ:
// it serves `rtusim replay`, which reports counts only.
#pragma once
#include <array>
#include <bit>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "cache/cache_params.h"

namespace rtusim {

class Lru4Cache {
 public:
  static constexpr uint32_t kWays = 4;

  // Whether `p` (valid) is a cache this type models: 4 ways, LRU.
  static bool fits(const CacheParams& p) { return p.assoc == kWays && p.policy == "lru"; }

  // `p` must be valid and fit().
  explicit Lru4Cache(const CacheParams& p)
      : line_bytes_(p.line_bytes),
        offset_bits_(static_cast<uint32_t>(std::countr_zero(p.line_bytes))),
        index_bits_(static_cast<uint32_t>(std::countr_zero(p.sets()))),
        set_mask_(p.sets() - 1),
        sets_(p.sets()) {}

  // Replays single-line accesses; returns the misses among them.
  uint64_t replay(std::span<const uint64_t> addrs) {
    uint64_t missed = 0;
    for (const uint64_t a : addrs) missed += lookup_fill(a >> offset_bits_) ? 0 : 1;
    accesses_ += addrs.size();
    misses_ += missed;
    return missed;
  }

  // Accesses every line that bytes [addr, addr + bytes) touch, in address order, each counted as
  // one access. Returns the lines missed.
  uint32_t access_range(uint64_t addr, uint32_t bytes) {
    if (bytes == 0) return 0;
    const uint64_t first = addr >> offset_bits_;
    const uint64_t last = (addr + bytes - 1) >> offset_bits_;
    uint32_t missed = 0;
    for (uint64_t line = first; line <= last; ++line) missed += lookup_fill(line) ? 0 : 1;
    accesses_ += last - first + 1;
    misses_ += missed;
    return missed;
  }

  uint64_t accesses() const { return accesses_; }
  uint64_t misses() const { return misses_; }
  uint64_t bytes_from_dram() const { return misses_ * line_bytes_; }

 private:
  // Tags are line >> index_bits < 2^62: all ones is no line's (an empty way).
  static constexpr uint64_t kEmpty = ~uint64_t{0};

  struct alignas(32) Set {
    std::array<uint64_t, kWays> tags{kEmpty, kEmpty, kEmpty, kEmpty};  // most recent first
  };

  // Looks `line` up and makes it the set's most recent; on a miss the least recent falls out.
  bool lookup_fill(uint64_t line) {
    uint64_t* t = sets_[line & set_mask_].tags.data();
    const uint64_t tag = line >> index_bits_;
#if defined(__AVX2__)
    // Lanes 1..k take the tags 0..k-1, the lanes after k keep theirs, lane 0 gets the tag:
    // k = the hit way, or 3 on a miss (the least recent falls out). As 32-bit lane indices.
    alignas(32) static constexpr uint32_t kMoveUp[kWays][8] = {
        {0, 1, 2, 3, 4, 5, 6, 7}, {0, 1, 0, 1, 4, 5, 6, 7},
        {0, 1, 0, 1, 2, 3, 6, 7}, {0, 1, 0, 1, 2, 3, 4, 5}};
    const __m256i tags = _mm256_load_si256(reinterpret_cast<const __m256i*>(t));
    const __m256i want = _mm256_set1_epi64x(static_cast<long long>(tag));
    const unsigned hit_mask = static_cast<unsigned>(
        _mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpeq_epi64(tags, want))));
    const unsigned k = static_cast<unsigned>(std::countr_zero(hit_mask | 8u));
    const __m256i moved = _mm256_permutevar8x32_epi32(
        tags, _mm256_load_si256(reinterpret_cast<const __m256i*>(kMoveUp[k])));
    _mm256_store_si256(reinterpret_cast<__m256i*>(t), _mm256_blend_epi32(moved, want, 0x03));
    return hit_mask != 0;
#else
    uint32_t k = kWays - 1;  // a miss: the least recent falls out
    bool hit = false;
    for (uint32_t w = 0; w < kWays; ++w) {
      const bool same = t[w] == tag;
      k = same ? w : k;
      hit |= same;
    }
    for (uint32_t w = k; w > 0; --w) t[w] = t[w - 1];
    t[0] = tag;
    return hit;
#endif
  }

  uint64_t line_bytes_;
  uint32_t offset_bits_, index_bits_;
  uint64_t set_mask_;
  std::vector<Set> sets_;
  uint64_t accesses_ = 0, misses_ = 0;
};

}  // namespace rtusim
