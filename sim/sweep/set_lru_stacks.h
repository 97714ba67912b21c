// LRU stack distances within the sets of one set count (Mattson et al. 1970, per set as in Hill &
// Smith 1989): one pass gives the hits of every associativity up to `depth` at this set count.
// A line at distance d (0 = most recent in its set) hits in every LRU cache of this set count
// with more than d ways; the cache fills invalid ways first, which LRU treats as oldest, so the
// inclusion property holds exactly.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__AVX2__)
#include <immintrin.h>
#elif defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace rtusim {

// One set's LRU stack of `depth` lines at `s`, most recent first: finds `tag`, moves it to the
// top and returns its distance before (depth when it was not there; the last line drops out).
inline uint32_t lru_stack_access(uint32_t* s, uint32_t tag, uint32_t depth) {
  uint32_t d = 0;
  while (d < depth && s[d] != tag) ++d;
  for (uint32_t i = d < depth ? d : depth - 1; i > 0; --i) s[i] = s[i - 1];
  s[0] = tag;
  return d;
}

class SetLruStacks {
 public:
  SetLruStacks(uint32_t sets, uint32_t depth);

  // Accesses `line`; returns its stack distance in its set before the access, or depth() when it
  // was deeper (or never seen). The line becomes the most recent of its set.
  uint32_t access(uint64_t line) {
    const auto tag = static_cast<uint32_t>(line);
    uint32_t* s = &stacks_[offset_ + (line & set_mask_) * stride_];
#if defined(__AVX2__) || defined(__SSE2__)
    if (stride_ == kVector) return access8(s, tag);
#endif
    return lru_stack_access(s, tag, depth_);
  }

  uint32_t sets() const { return static_cast<uint32_t>(set_mask_ + 1); }
  uint32_t depth() const { return depth_; }

 private:
  static constexpr uint32_t kEmpty = ~uint32_t{0};  // never a line number (lines < 2^32 - 1)
  static constexpr uint32_t kVector = 8;            // stacks of depth <= 8 are padded to 8

#if defined(__AVX2__)
  // The same on an 8-entry stack in one AVX2 register (a set is one aligned 32-byte block): one
  // compare finds the line, and the stack rotated up one lane, the line in lane 0, is blended in
  // under a lane mask for lanes 0..moved (no branch but the hit test). The padding lanes
  // (depth_ and up) are never written, so they stay kEmpty.
  uint32_t access8(uint32_t* s, uint32_t tag) {
    const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256i key = _mm256_set1_epi32(static_cast<int>(tag));
    const __m256i v = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(s));
    const unsigned found =
        static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(v, key))));
    uint32_t d = found ? static_cast<uint32_t>(__builtin_ctz(found)) : kVector;
    if (d > depth_) d = depth_;
    if (d == 0) return 0;  // already the most recent: nothing moves
    const uint32_t moved = d < depth_ ? d : depth_ - 1;
    const __m256i up = _mm256_blend_epi32(
        _mm256_permutevar8x32_epi32(v, _mm256_setr_epi32(0, 0, 1, 2, 3, 4, 5, 6)), key, 1);
    const __m256i take = _mm256_cmpgt_epi32(_mm256_set1_epi32(static_cast<int>(moved + 1)), lanes);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(s), _mm256_blendv_epi8(v, up, take));
    return d;
  }
#elif defined(__SSE2__)
  // The same on an 8-entry stack in two SSE2 registers: one compare finds the line, and one
  // shifted copy blended under a lane mask moves the lines above it down (no branch but the
  // hit test). The padding lanes (depth_ and up) are never written, so they stay kEmpty.
  uint32_t access8(uint32_t* s, uint32_t tag) {
    const __m128i key = _mm_set1_epi32(static_cast<int>(tag));
    const __m128i lo = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s));
    const __m128i hi = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s + 4));
    const int found = _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(lo, key))) |
                      (_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(hi, key))) << 4);
    uint32_t d = found ? static_cast<uint32_t>(__builtin_ctz(static_cast<unsigned>(found))) : kVector;
    if (d > depth_) d = depth_;
    const uint32_t moved = d < depth_ ? d : depth_ - 1;
    // Lanes 0..moved take their upper neighbour's old value (lane 0 the line); the rest stay.
    const __m128i lo_shift = _mm_or_si128(_mm_slli_si128(lo, 4), _mm_cvtsi32_si128(static_cast<int>(tag)));
    const __m128i hi_shift = _mm_or_si128(_mm_slli_si128(hi, 4), _mm_srli_si128(lo, 12));
    const __m128i limit = _mm_set1_epi32(static_cast<int>(moved + 1));
    const __m128i take_lo = _mm_cmpgt_epi32(limit, _mm_setr_epi32(0, 1, 2, 3));  // lane <= moved
    const __m128i take_hi = _mm_cmpgt_epi32(limit, _mm_setr_epi32(4, 5, 6, 7));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(s),
                     _mm_or_si128(_mm_and_si128(take_lo, lo_shift), _mm_andnot_si128(take_lo, lo)));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(s + 4),
                     _mm_or_si128(_mm_and_si128(take_hi, hi_shift), _mm_andnot_si128(take_hi, hi)));
    return d;
  }
#endif

  uint64_t set_mask_;
  uint32_t depth_;
  uint32_t stride_;               // entries per set: depth_, or kVector when depth_ <= kVector
  std::vector<uint32_t> stacks_;  // [offset + set * stride + distance]: lines, most recent first
  size_t offset_ = 0;             // entries before the first set, which starts 32-byte aligned
};

}  // namespace rtusim
