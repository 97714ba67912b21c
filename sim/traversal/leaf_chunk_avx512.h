// The watertight test of up to 16 triangles of a leaf against one ray at once (AVX-512), with
// the very float operations of intersect_watertight() in the same order, lane by lane, so every
// result is bit-identical to the scalar test. Lanes the scalar test would send to one of its
// rare paths (a zero barycentric, t to refine in double) are left to the scalar test.
#pragma once
#if defined(__AVX512F__)
#include <immintrin.h>

#include <cstdint>

#include "traversal/watertight_triangle.h"

namespace rtusim {

// What the 16-lane test leaves for the in-order pass over a chunk: the lanes that may hit, the
// lanes to test with the scalar test, and per lane the values the last step needs.
struct LeafChunk {
  static constexpr int kLanes = 16;
  uint32_t hit_mask = 0;     // lanes that hit within the t limit the chunk was tested against
  uint32_t scalar_mask = 0;  // lanes on one of the scalar test's rare paths
  alignas(64) float T[kLanes], det[kLanes], inv[kLanes], V[kLanes], W[kLanes];

  // Tests the `lanes` (1..16) triangles whose ids are at `ids` and whose vertices (nine floats
  // each) lie at byte `tri_base + 36 * id` of `bytes` (every such offset below 2^31) against
  // ray `r` over (0, t_limit). A lane rejected here is rejected for any smaller limit too.
  void test(const WatertightRay& r, const uint8_t* bytes, uint64_t tri_base, const uint8_t* ids,
            int lanes, float t_limit);

  // The last step for lane `i` against the current limit `t_max`: as intersect_watertight()
  // ends for a triangle whose t needs no refinement. Sets t and the barycentrics on a hit.
  bool accept(int i, float t_max, float& t, float& bu, float& bv) const {
    if (!watertight_detail::t_in_range(T[i], det[i], inv[i], t_max, t)) return false;
    bu = V[i] * inv[i];
    bv = W[i] * inv[i];
    return true;
  }
};

namespace leaf_chunk_detail {
inline __m512 abs16(__m512 x) {
  return _mm512_castsi512_ps(
      _mm512_and_si512(_mm512_castps_si512(x), _mm512_set1_epi32(0x7fffffff)));
}
// std::max(a, b) lane by lane: (a < b) ? b : a.
inline __m512 max16(__m512 a, __m512 b) {
  return _mm512_mask_blend_ps(_mm512_cmp_ps_mask(a, b, _CMP_LT_OQ), a, b);
}
inline __m512 max3_16(__m512 a, __m512 b, __m512 c) { return max16(max16(a, b), c); }
}  // namespace leaf_chunk_detail

inline void LeafChunk::test(const WatertightRay& r, const uint8_t* bytes, uint64_t tri_base,
                            const uint8_t* ids, int lanes, float t_limit) {
  using namespace leaf_chunk_detail;
  using watertight_detail::gamma_f;
  const __mmask16 live = static_cast<__mmask16>((1u << lanes) - 1u);
  const __m512 zero = _mm512_setzero_ps();

  // Gathers: byte offsets of the triangles, then each coordinate the ray's permutation needs.
  const __m512i id = _mm512_maskz_loadu_epi32(live, ids);
  const __m512i off = _mm512_add_epi32(_mm512_mullo_epi32(id, _mm512_set1_epi32(36)),
                                       _mm512_set1_epi32(static_cast<int>(tri_base)));
  auto coord = [&](int vertex, int axis) {
    return _mm512_mask_i32gather_ps(zero, live, off, bytes + 4 * (3 * vertex + axis), 1);
  };

  // Vertices relative to the ray origin, permuted and sheared into ray space.
  const __m512 ox = _mm512_set1_ps(r.ox), oy = _mm512_set1_ps(r.oy), oz = _mm512_set1_ps(r.oz);
  const __m512 sx = _mm512_set1_ps(r.sx), sy = _mm512_set1_ps(r.sy), sz = _mm512_set1_ps(r.sz);
  const __m512 Az = _mm512_sub_ps(coord(0, r.kz), oz);
  const __m512 Bz = _mm512_sub_ps(coord(1, r.kz), oz);
  const __m512 Cz = _mm512_sub_ps(coord(2, r.kz), oz);
  auto shear = [&](__m512 p, __m512 o, __m512 s, __m512 z) {
    return _mm512_sub_ps(_mm512_sub_ps(p, o), _mm512_mul_ps(s, z));
  };
  const __m512 Ax = shear(coord(0, r.kx), ox, sx, Az), Ay = shear(coord(0, r.ky), oy, sy, Az);
  const __m512 Bx = shear(coord(1, r.kx), ox, sx, Bz), By = shear(coord(1, r.ky), oy, sy, Bz);
  const __m512 Cx = shear(coord(2, r.kx), ox, sx, Cz), Cy = shear(coord(2, r.ky), oy, sy, Cz);

  // Scaled barycentrics; a lane with one exactly zero goes to the scalar test.
  auto diff_of_products = [](__m512 a, __m512 b, __m512 c, __m512 d) {
    return _mm512_sub_ps(_mm512_mul_ps(a, b), _mm512_mul_ps(c, d));
  };
  const __m512 U = diff_of_products(Cx, By, Cy, Bx);
  const __m512 Vb = diff_of_products(Ax, Cy, Ay, Cx);
  const __m512 Wb = diff_of_products(Bx, Ay, By, Ax);
  const __mmask16 any_zero = _mm512_cmp_ps_mask(U, zero, _CMP_EQ_OQ) |
                             _mm512_cmp_ps_mask(Vb, zero, _CMP_EQ_OQ) |
                             _mm512_cmp_ps_mask(Wb, zero, _CMP_EQ_OQ);
  const __mmask16 any_neg = _mm512_cmp_ps_mask(U, zero, _CMP_LT_OQ) |
                            _mm512_cmp_ps_mask(Vb, zero, _CMP_LT_OQ) |
                            _mm512_cmp_ps_mask(Wb, zero, _CMP_LT_OQ);
  const __mmask16 any_pos = _mm512_cmp_ps_mask(U, zero, _CMP_GT_OQ) |
                            _mm512_cmp_ps_mask(Vb, zero, _CMP_GT_OQ) |
                            _mm512_cmp_ps_mask(Wb, zero, _CMP_GT_OQ);
  const __m512 det_s = _mm512_add_ps(_mm512_add_ps(U, Vb), Wb);
  // Still in play: signs agree and the determinant is not zero.
  const __mmask16 candidate = live & ~any_zero & ~(any_neg & any_pos) &
                              _mm512_cmp_ps_mask(det_s, zero, _CMP_NEQ_UQ);

  // Scaled hit distance T = t * det.
  const __m512 zA = _mm512_mul_ps(sz, Az), zB = _mm512_mul_ps(sz, Bz), zC = _mm512_mul_ps(sz, Cz);
  const __m512 T_s = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(U, zA), _mm512_mul_ps(Vb, zB)),
                                 _mm512_mul_ps(Wb, zC));
  const __m512 inv_s = _mm512_div_ps(_mm512_set1_ps(1.0f), det_s);

  // t's rounding-error bound, as the scalar test forms it; lanes to refine go to it.
  const __m512 g2 = _mm512_set1_ps(gamma_f(2)), g3 = _mm512_set1_ps(gamma_f(3)),
               g5 = _mm512_set1_ps(gamma_f(5));
  const __m512 max_zt = max3_16(abs16(zA), abs16(zB), abs16(zC));
  const __m512 max_xt = max3_16(abs16(Ax), abs16(Bx), abs16(Cx));
  const __m512 max_yt = max3_16(abs16(Ay), abs16(By), abs16(Cy));
  const __m512 delta_x = _mm512_mul_ps(g5, _mm512_add_ps(max_xt, max_zt));
  const __m512 delta_y = _mm512_mul_ps(g5, _mm512_add_ps(max_yt, max_zt));
  const __m512 delta_z = _mm512_mul_ps(g3, max_zt);
  const __m512 delta_e = _mm512_mul_ps(
      _mm512_set1_ps(2.0f),
      _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(_mm512_mul_ps(g2, max_xt), max_yt),
                                  _mm512_mul_ps(delta_y, max_xt)),
                    _mm512_mul_ps(delta_x, max_yt)));
  const __m512 max_e = max3_16(abs16(U), abs16(Vb), abs16(Wb));
  const __m512 delta_t = _mm512_mul_ps(
      _mm512_mul_ps(_mm512_set1_ps(3.0f),
                    _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(_mm512_mul_ps(g3, max_e), max_zt),
                                                _mm512_mul_ps(delta_e, max_zt)),
                                  _mm512_mul_ps(delta_z, max_e))),
      abs16(inv_s));
  const __mmask16 refine =
      _mm512_cmp_ps_mask(abs16(_mm512_mul_ps(T_s, inv_s)),
                         _mm512_mul_ps(_mm512_set1_ps(watertight_detail::kRefineAbove), delta_t),
                         _CMP_LE_OQ);

  // The last step against t_limit (t_in_range() lane by lane).
  const __m512 t_max = _mm512_set1_ps(t_limit);
  const __m512 T_limit = _mm512_mul_ps(t_max, det_s);
  const __mmask16 positive = _mm512_cmp_ps_mask(det_s, zero, _CMP_GT_OQ);
  const __mmask16 outside =
      (positive & (_mm512_cmp_ps_mask(T_s, zero, _CMP_LE_OQ) |
                   _mm512_cmp_ps_mask(T_s, T_limit, _CMP_GE_OQ))) |
      (~positive & (_mm512_cmp_ps_mask(T_s, zero, _CMP_GE_OQ) |
                    _mm512_cmp_ps_mask(T_s, T_limit, _CMP_LE_OQ)));
  const __m512 t = _mm512_mul_ps(T_s, inv_s);
  const __mmask16 in_range = ~outside & _mm512_cmp_ps_mask(t, zero, _CMP_GT_OQ) &
                             _mm512_cmp_ps_mask(t, t_max, _CMP_LT_OQ);

  scalar_mask = (live & any_zero) | (candidate & refine);
  hit_mask = candidate & ~refine & in_range;
  _mm512_store_ps(T, T_s);
  _mm512_store_ps(det, det_s);
  _mm512_store_ps(inv, inv_s);
  _mm512_store_ps(V, Vb);
  _mm512_store_ps(W, Wb);
}

}  // namespace rtusim
#endif
