// The vector operations of an 8-lane RayPacket (AVX2; AVX-512 hosts use it too): one float per
// lane in a __m256, lane masks as __m256 compare results (all ones in a lane that is in). The
// same IEEE operations and predicates as traverse()'s scalar code, so each lane computes the
// same values.
#pragma once
#if defined(__AVX2__)
#include <immintrin.h>

#include <cstdint>

namespace rtusim {

struct PacketSimd8 {
  static constexpr int kLanes = 8;
  using Vec = __m256;

  // A lane mask: all ones in the lanes that are in, zero elsewhere; & | ~ lane by lane.
  struct Mask {
    __m256i v;
    friend Mask operator&(Mask a, Mask b) { return {_mm256_and_si256(a.v, b.v)}; }
    friend Mask operator|(Mask a, Mask b) { return {_mm256_or_si256(a.v, b.v)}; }
    // ~a on its own is rarely wanted: a & ~b is one and-not.
    struct Not {
      __m256i v;
    };
    friend Not operator~(Mask a) { return {a.v}; }
    friend Mask operator&(Mask a, Not b) { return {_mm256_andnot_si256(b.v, a.v)}; }
  };

  static Vec load(const float* p) { return _mm256_load_ps(p); }
  static void store(float* p, Vec v) { _mm256_store_ps(p, v); }
  static Vec set1(float x) { return _mm256_set1_ps(x); }
  static Vec zero() { return _mm256_setzero_ps(); }
  static Vec add(Vec a, Vec b) { return _mm256_add_ps(a, b); }
  static Vec sub(Vec a, Vec b) { return _mm256_sub_ps(a, b); }
  static Vec mul(Vec a, Vec b) { return _mm256_mul_ps(a, b); }
  static Vec abs(Vec a) { return _mm256_andnot_ps(_mm256_set1_ps(-0.0f), a); }

  // The lanes of `active` where a < b, a <= b, a > b, !(a > b) (true for NaN).
  static Mask lt(Mask active, Vec a, Vec b) { return active & cmp<_CMP_LT_OQ>(a, b); }
  static Mask le(Mask active, Vec a, Vec b) { return active & cmp<_CMP_LE_OQ>(a, b); }
  static Mask gt(Mask active, Vec a, Vec b) { return active & cmp<_CMP_GT_OQ>(a, b); }
  static Mask ngt(Mask active, Vec a, Vec b) { return active & cmp<_CMP_NGT_UQ>(a, b); }
  // b in the lanes of m, a elsewhere.
  static Vec blend(Mask m, Vec a, Vec b) {
    return _mm256_blendv_ps(a, b, _mm256_castsi256_ps(m.v));
  }

  static Mask from_bits(uint32_t bits) {
    const __m256i lane_bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    return {_mm256_cmpeq_epi32(
        _mm256_and_si256(_mm256_set1_epi32(static_cast<int>(bits)), lane_bit), lane_bit)};
  }
  static uint32_t bits(Mask m) {
    return static_cast<uint32_t>(_mm256_movemask_ps(_mm256_castsi256_ps(m.v)));
  }
  static bool any(Mask m) { return !_mm256_testz_si256(m.v, m.v); }

 private:
  template <int kPredicate>
  static Mask cmp(Vec a, Vec b) {
    return {_mm256_castps_si256(_mm256_cmp_ps(a, b, kPredicate))};
  }
};

}  // namespace rtusim
#endif
