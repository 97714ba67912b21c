// The vector operations of a 16-lane RayPacket (AVX-512): one float per lane in a __m512, lane
// masks in a __mmask16. Each operation is the one intrinsic the 16-lane packet was written with.
#pragma once
#if defined(__AVX512F__)
#include <immintrin.h>

#include <cstdint>

namespace rtusim {

struct PacketSimd16 {
  static constexpr int kLanes = 16;
  using Vec = __m512;
  using Mask = __mmask16;  // bit i: lane i

  static Vec load(const float* p) { return _mm512_load_ps(p); }
  static void store(float* p, Vec v) { _mm512_store_ps(p, v); }
  static Vec set1(float x) { return _mm512_set1_ps(x); }
  static Vec zero() { return _mm512_setzero_ps(); }
  static Vec add(Vec a, Vec b) { return _mm512_add_ps(a, b); }
  static Vec sub(Vec a, Vec b) { return _mm512_sub_ps(a, b); }
  static Vec mul(Vec a, Vec b) { return _mm512_mul_ps(a, b); }
  static Vec abs(Vec a) { return _mm512_abs_ps(a); }

  // The lanes of `active` where a < b, a <= b, a > b, !(a > b) (true for NaN).
  static Mask lt(Mask active, Vec a, Vec b) {
    return _mm512_mask_cmp_ps_mask(active, a, b, _CMP_LT_OQ);
  }
  static Mask le(Mask active, Vec a, Vec b) {
    return _mm512_mask_cmp_ps_mask(active, a, b, _CMP_LE_OQ);
  }
  static Mask gt(Mask active, Vec a, Vec b) {
    return _mm512_mask_cmp_ps_mask(active, a, b, _CMP_GT_OQ);
  }
  static Mask ngt(Mask active, Vec a, Vec b) {
    return _mm512_mask_cmp_ps_mask(active, a, b, _CMP_NGT_UQ);
  }
  // b in the lanes of m, a elsewhere.
  static Vec blend(Mask m, Vec a, Vec b) { return _mm512_mask_blend_ps(m, a, b); }

  static Mask from_bits(uint32_t bits) { return static_cast<__mmask16>(bits); }
  static uint32_t bits(Mask m) { return m; }
  static bool any(Mask m) { return m != 0; }
};

}  // namespace rtusim
#endif
