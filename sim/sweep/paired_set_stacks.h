// The LRU stacks of several set counts of one line size, each at most 8 ways deep, walked two
// set counts per step: with AVX-512 the two sets (8 lanes each, one aligned 32-byte block per
// set) are one 16-lane register, so one compare finds the line in both and one masked permute
// moves both stacks. Set counts in increasing order: a line that is the most recent of its set
// at s sets is also the most recent at every larger set count, where the access then changes
// nothing (Hill & Smith's set refinement), so the walk stops after the first pair where the
// line was already the most recent. Distances as in SetLruStacks.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sweep/set_lru_stacks.h"

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace rtusim {

class PairedSetStacks {
 public:
  static constexpr uint32_t kMaxDepth = 8;
  static constexpr uint32_t kStride = kMaxDepth + 1;  // histogram entries per set count

  // `sets[e]`: powers of two, increasing; `depths[e]`: 1 .. kMaxDepth.
  PairedSetStacks(const std::vector<uint64_t>& sets, const std::vector<uint32_t>& depths);
  PairedSetStacks(const PairedSetStacks&) = delete;
  PairedSetStacks& operator=(const PairedSetStacks&) = delete;

  // Accesses `line` in every set count the walk reaches: adds 1 to hist[e * kStride + d] for each
  // set count e walked, d its distance (depth when deeper); returns the first set count not
  // walked (size() when all were), where the line was the most recent.
  size_t access(uint64_t line, uint64_t* __restrict hist) {
    const auto tag = static_cast<uint32_t>(line);
    for (size_t p = 0; p < pair_.size(); ++p) {
      const Pair& q = pair_[p];
      uint32_t* sa = q.a + size_t{tag & q.mask_a} * kMaxDepth;
      uint32_t* sb = q.b + size_t{tag & q.mask_b} * kMaxDepth;
      uint32_t da, db;
      access_pair(sa, sb, tag, q, da, db);
      ++hist[2 * p * kStride + da];
      ++hist[(2 * p + 1) * kStride + db];
      if (db == 0) return 2 * p + 2;
    }
    return 2 * pair_.size();
  }

  // Set counts walked, with one of a single set appended when the count is odd.
  size_t size() const { return 2 * pair_.size(); }

 private:
  static constexpr uint32_t kEmpty = ~uint32_t{0};  // never a line number (lines < 2^32 - 1)
  // Two set counts walked in one step: their first sets, set masks, and per half the bit just
  // above its depth (1 << depth) and, in `lanes`, the lanes below its depth.
  struct Pair {
    uint32_t* a;
    uint32_t* b;
    uint32_t mask_a, mask_b;
    uint32_t beyond_a, beyond_b;
    uint32_t lanes;
  };

  // Finds `tag` in both sets and moves it to the top of each; da, db its distances before.
  static void access_pair(uint32_t* sa, uint32_t* sb, uint32_t tag, const Pair& q, uint32_t& da,
                          uint32_t& db) {
#if defined(__AVX512F__) && defined(__BMI__)
    // GCC 12 warns of its own intrinsics' undefined upper halves (GCC bug 105593).
#if !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
    const __m512i key = _mm512_set1_epi32(static_cast<int>(tag));
    const __m512i v = _mm512_inserti64x4(
        _mm512_castsi256_si512(_mm256_load_si256(reinterpret_cast<const __m256i*>(sa))),
        _mm256_load_si256(reinterpret_cast<const __m256i*>(sb)), 1);
    const uint32_t found = _mm512_cmpeq_epi32_mask(v, key);
    const uint32_t found_a = found & 0xffu, found_b = found >> 8;
    da = _tzcnt_u32(found_a | q.beyond_a);
    db = _tzcnt_u32(found_b | q.beyond_b);
    // Lanes 0..d of each half (all its lanes on a miss: the mask up to the lowest set bit, all
    // ones when none) take their upper neighbour's old value, lane 0 the line.
    const auto take = static_cast<__mmask16>(
        ((_blsmsk_u32(found_a) & 0xffu) | (_blsmsk_u32(found_b) << 8)) & q.lanes);
    const __m512i up = _mm512_mask_mov_epi32(
        _mm512_permutexvar_epi32(
            _mm512_setr_epi32(0, 0, 1, 2, 3, 4, 5, 6, 8, 8, 9, 10, 11, 12, 13, 14), v),
        0x0101, key);
    const __m512i out = _mm512_mask_mov_epi32(v, take, up);
    _mm256_store_si256(reinterpret_cast<__m256i*>(sa), _mm512_castsi512_si256(out));
    _mm256_store_si256(reinterpret_cast<__m256i*>(sb), _mm512_extracti64x4_epi64(out, 1));
#if !defined(__clang__)
#pragma GCC diagnostic pop
#endif
#else
    da = lru_stack_access(sa, tag, static_cast<uint32_t>(__builtin_ctz(q.beyond_a)));
    db = lru_stack_access(sb, tag, static_cast<uint32_t>(__builtin_ctz(q.beyond_b)));
#endif
  }

  std::vector<Pair> pair_;
  std::vector<uint32_t> storage_;  // the sets, kMaxDepth entries each, from a 64-byte boundary
};

}  // namespace rtusim
