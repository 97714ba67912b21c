// The watertight triangle test (watertight_triangle.h) of one triangle against up to 8 rays at
// once (AVX2): each lane computes intersect_watertight()'s own float operations in the same
// order, its vertex coordinates picked by its own axis permutation, so a lane's outcome is the
// single-ray test's bit for bit. The two rare cases that leave float arithmetic (a scaled
// barycentric exactly zero, a t that needs refining in double) are flagged for the caller to
// test with the single-ray code.
#pragma once
#if defined(__AVX2__)
#include <immintrin.h>

#include <cstdint>
#include <limits>

#include "traversal/packet_simd8.h"
#include "traversal/watertight_triangle.h"

namespace rtusim {

class WatertightLanes8 {
 public:
  static constexpr int kLanes = 8;

  // What one triangle's test gives, lane by lane (masks: all ones in a lane that is in).
  struct Outcome {
    __m256 hit;     // a hit within the lane's t_max: t, u, v hold it
    __m256 scalar;  // to be tested with the single-ray code instead
    __m256 t, u, v;
  };

  // Sets lane `lane` to ray `r`.
  void set_lane(int lane, const WatertightRay& r) {
    ox_[lane] = r.ox;
    oy_[lane] = r.oy;
    oz_[lane] = r.oz;
    sx_[lane] = r.sx;
    sy_[lane] = r.sy;
    sz_[lane] = r.sz;
    kx_[lane] = r.kx;
    ky_[lane] = r.ky;
    kz_[lane] = r.kz;
  }

  // Tests the triangle whose nine floats (x, y, z of each vertex) lie at `v` against the lanes
  // of `todo`, each over (0, t_max of its lane).
  [[gnu::always_inline]] Outcome test(const uint8_t* v, __m256 todo, __m256 t_max) const {
    using namespace watertight_detail;
    // Floats 0..7 and 1..8 of the triangle: vertex A's and B's coordinates from the first,
    // C's from the second; lane by lane the one its permutation picks.
    const __m256 lo = _mm256_loadu_ps(reinterpret_cast<const float*>(v));
    const __m256 hi = _mm256_loadu_ps(reinterpret_cast<const float*>(v) + 1);
    const __m256i three = _mm256_set1_epi32(3), five = _mm256_set1_epi32(5);
    auto coords = [&](const int32_t* k, __m256& a, __m256& b, __m256& c) {
      const __m256i idx = _mm256_load_si256(reinterpret_cast<const __m256i*>(k));
      a = _mm256_permutevar8x32_ps(lo, idx);
      b = _mm256_permutevar8x32_ps(lo, _mm256_add_epi32(idx, three));
      c = _mm256_permutevar8x32_ps(hi, _mm256_add_epi32(idx, five));
    };
    __m256 px[3], py[3], pz[3];
    coords(kx_, px[0], px[1], px[2]);
    coords(ky_, py[0], py[1], py[2]);
    coords(kz_, pz[0], pz[1], pz[2]);
    // Relative to the origin, permuted and sheared: Z = p_z - oz, X = (p_x - ox) - sx Z, ...
    const __m256 ox = _mm256_load_ps(ox_), oy = _mm256_load_ps(oy_), oz = _mm256_load_ps(oz_);
    const __m256 sx = _mm256_load_ps(sx_), sy = _mm256_load_ps(sy_), sz = _mm256_load_ps(sz_);
    __m256 X[3], Y[3], Z[3];
    for (int i = 0; i < 3; ++i) {
      Z[i] = _mm256_sub_ps(pz[i], oz);
      X[i] = _mm256_sub_ps(_mm256_sub_ps(px[i], ox), _mm256_mul_ps(sx, Z[i]));
      Y[i] = _mm256_sub_ps(_mm256_sub_ps(py[i], oy), _mm256_mul_ps(sy, Z[i]));
    }
    // U, V, W = Cx By - Cy Bx, Ax Cy - Ay Cx, Bx Ay - By Ax.
    const __m256 U = _mm256_sub_ps(_mm256_mul_ps(X[2], Y[1]), _mm256_mul_ps(Y[2], X[1]));
    const __m256 V = _mm256_sub_ps(_mm256_mul_ps(X[0], Y[2]), _mm256_mul_ps(Y[0], X[2]));
    const __m256 W = _mm256_sub_ps(_mm256_mul_ps(X[1], Y[0]), _mm256_mul_ps(Y[1], X[0]));
    const __m256 zero = _mm256_setzero_ps();
    // One exactly zero: the single-ray code (it recomputes them in double).
    const __m256 any_zero =
        _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(U, zero, _CMP_EQ_OQ),
                                  _mm256_cmp_ps(V, zero, _CMP_EQ_OQ)),
                     _mm256_cmp_ps(W, zero, _CMP_EQ_OQ));
    // Mixed signs: outside.
    const __m256 neg = _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(U, zero, _CMP_LT_OQ),
                                                 _mm256_cmp_ps(V, zero, _CMP_LT_OQ)),
                                    _mm256_cmp_ps(W, zero, _CMP_LT_OQ));
    const __m256 pos = _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(U, zero, _CMP_GT_OQ),
                                                 _mm256_cmp_ps(V, zero, _CMP_GT_OQ)),
                                    _mm256_cmp_ps(W, zero, _CMP_GT_OQ));
    const __m256 det = _mm256_add_ps(_mm256_add_ps(U, V), W);
    // In play: not zero, not outside, det != 0 (the single-ray test's early returns).
    const __m256 in_play = _mm256_andnot_ps(
        _mm256_or_ps(any_zero, _mm256_and_ps(neg, pos)),
        _mm256_and_ps(todo, _mm256_cmp_ps(det, zero, _CMP_NEQ_UQ)));
    Outcome o;
    if (_mm256_testz_ps(in_play, in_play) && _mm256_testz_ps(todo, any_zero)) {
      o.hit = o.scalar = zero;
      return o;
    }
    // T = t det, and t's rounding-error bound, as in intersect_watertight().
    const __m256 zA = _mm256_mul_ps(sz, Z[0]), zB = _mm256_mul_ps(sz, Z[1]),
                 zC = _mm256_mul_ps(sz, Z[2]);
    const __m256 T = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(U, zA), _mm256_mul_ps(V, zB)),
                                   _mm256_mul_ps(W, zC));
    const __m256 inv = _mm256_div_ps(_mm256_set1_ps(1.0f), det);
    const __m256 max_zt = max3(abs(zA), abs(zB), abs(zC));
    const __m256 max_xt = max3(abs(X[0]), abs(X[1]), abs(X[2]));
    const __m256 max_yt = max3(abs(Y[0]), abs(Y[1]), abs(Y[2]));
    const __m256 g5 = _mm256_set1_ps(gamma_f(5)), g3 = _mm256_set1_ps(gamma_f(3));
    const __m256 delta_x = _mm256_mul_ps(g5, _mm256_add_ps(max_xt, max_zt));
    const __m256 delta_y = _mm256_mul_ps(g5, _mm256_add_ps(max_yt, max_zt));
    const __m256 delta_z = _mm256_mul_ps(g3, max_zt);
    const __m256 delta_e = _mm256_mul_ps(
        _mm256_set1_ps(2.0f),
        _mm256_add_ps(
            _mm256_add_ps(
                _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(gamma_f(2)), max_xt), max_yt),
                _mm256_mul_ps(delta_y, max_xt)),
            _mm256_mul_ps(delta_x, max_yt)));
    const __m256 max_e = max3(abs(U), abs(V), abs(W));
    const __m256 delta_t = _mm256_mul_ps(
        _mm256_mul_ps(
            _mm256_set1_ps(3.0f),
            _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_mul_ps(g3, max_e), max_zt),
                                        _mm256_mul_ps(delta_e, max_zt)),
                          _mm256_mul_ps(delta_z, max_e))),
        abs(inv));
    const __m256 t = _mm256_mul_ps(T, inv);
    // t to be refined in double, or T overflowed: the single-ray code.
    const __m256 refine = _mm256_or_ps(
        _mm256_cmp_ps(abs(T), _mm256_set1_ps(std::numeric_limits<float>::max()), _CMP_NLE_UQ),
        _mm256_cmp_ps(abs(t), _mm256_mul_ps(_mm256_set1_ps(kRefineAbove), delta_t), _CMP_LE_OQ));
    // t_in_range(): T against (0, t_max det), then t itself against (0, t_max).
    const __m256 T_limit = _mm256_mul_ps(t_max, det);
    const __m256 positive = _mm256_cmp_ps(det, zero, _CMP_GT_OQ);
    const __m256 out_pos = _mm256_or_ps(_mm256_cmp_ps(T, zero, _CMP_LE_OQ),
                                        _mm256_cmp_ps(T, T_limit, _CMP_GE_OQ));
    const __m256 out_neg = _mm256_or_ps(_mm256_cmp_ps(T, zero, _CMP_GE_OQ),
                                        _mm256_cmp_ps(T, T_limit, _CMP_LE_OQ));
    const __m256 outside = _mm256_blendv_ps(out_neg, out_pos, positive);
    const __m256 in_range = _mm256_andnot_ps(
        outside, _mm256_and_ps(_mm256_cmp_ps(t, zero, _CMP_GT_OQ),
                               _mm256_cmp_ps(t, t_max, _CMP_LT_OQ)));
    o.scalar = _mm256_and_ps(todo, _mm256_or_ps(any_zero, _mm256_and_ps(in_play, refine)));
    o.hit = _mm256_and_ps(_mm256_andnot_ps(refine, in_play), in_range);
    o.t = t;
    o.u = _mm256_mul_ps(V, inv);
    o.v = _mm256_mul_ps(W, inv);
    return o;
  }

 private:
  static __m256 abs(__m256 x) { return PacketSimd8::abs(x); }
  // watertight_detail::max3(): std::max(std::max(a, b), c), std::max(a, b) being
  // (a < b) ? b : a, which is maxps(b, a) (b > a ? b : a), NaNs included.
  static __m256 max3(__m256 a, __m256 b, __m256 c) {
    return _mm256_max_ps(c, _mm256_max_ps(b, a));
  }

  alignas(32) float ox_[kLanes] = {}, oy_[kLanes] = {}, oz_[kLanes] = {};
  alignas(32) float sx_[kLanes] = {}, sy_[kLanes] = {}, sz_[kLanes] = {};
  alignas(32) int32_t kx_[kLanes] = {}, ky_[kLanes] = {}, kz_[kLanes] = {};
};

}  // namespace rtusim
#endif
