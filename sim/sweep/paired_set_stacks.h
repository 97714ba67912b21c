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
  size_t access(uint64_t line, uint64_t* hist) {
    const auto tag = static_cast<uint32_t>(line);
    for (size_t e = 0; e < engine_.size(); e += 2) {
      const Engine& a = engine_[e];
      const Engine& b = engine_[e + 1];
      uint32_t* sa = stacks_ + a.offset + (line & a.mask) * kMaxDepth;
      uint32_t* sb = stacks_ + b.offset + (line & b.mask) * kMaxDepth;
      uint32_t da, db;
      access_pair(sa, sb, tag, a.depth, b.depth, da, db);
      ++hist[e * kStride + da];
      ++hist[(e + 1) * kStride + db];
      if (db == 0) return e + 2;
    }
    return engine_.size();
  }

  // Set counts walked, with one of a single set appended when the count is odd.
  size_t size() const { return engine_.size(); }

 private:
  static constexpr uint32_t kEmpty = ~uint32_t{0};  // never a line number (lines < 2^32 - 1)
  struct Engine {
    size_t offset;  // first entry of its sets in stacks_
    uint64_t mask;  // sets - 1
    uint32_t depth;
  };

  // Finds `tag` in both sets and moves it to the top of each; da, db its distances before.
  static void access_pair(uint32_t* sa, uint32_t* sb, uint32_t tag, uint32_t depth_a,
                          uint32_t depth_b, uint32_t& da, uint32_t& db) {
#if defined(__AVX512F__)
    const __m512i key = _mm512_set1_epi32(static_cast<int>(tag));
    const __m512i v = _mm512_inserti64x4(
        _mm512_castsi256_si512(_mm256_load_si256(reinterpret_cast<const __m256i*>(sa))),
        _mm256_load_si256(reinterpret_cast<const __m256i*>(sb)), 1);
    const uint32_t found = _mm512_cmpeq_epi32_mask(v, key);
    da = _tzcnt_u32((found & 0xffu) | (1u << depth_a));
    db = _tzcnt_u32((found >> 8) | (1u << depth_b));
    // Lanes 0..moved of each half take their upper neighbour's old value, lane 0 the line.
    const uint32_t moved_a = da < depth_a ? da : depth_a - 1;
    const uint32_t moved_b = db < depth_b ? db : depth_b - 1;
    const auto take = static_cast<__mmask16>(((2u << moved_a) - 1) | (((2u << moved_b) - 1) << 8));
    const __m512i up = _mm512_mask_mov_epi32(
        _mm512_permutexvar_epi32(
            _mm512_setr_epi32(0, 0, 1, 2, 3, 4, 5, 6, 8, 8, 9, 10, 11, 12, 13, 14), v),
        0x0101, key);
    const __m512i out = _mm512_mask_mov_epi32(v, take, up);
    _mm256_store_si256(reinterpret_cast<__m256i*>(sa), _mm512_castsi512_si256(out));
    _mm256_store_si256(reinterpret_cast<__m256i*>(sb), _mm512_extracti64x4_epi64(out, 1));
#else
    da = lru_stack_access(sa, tag, depth_a);
    db = lru_stack_access(sb, tag, depth_b);
#endif
  }

  std::vector<Engine> engine_;
  std::vector<uint32_t> storage_;  // the sets, kMaxDepth entries each, from a 64-byte boundary
  uint32_t* stacks_ = nullptr;
};

}  // namespace rtusim
