// Watertight ray/triangle intersection (Woop, Benthin, Wald, JCGT 2013): rays through shared
// edges and vertices of a closed mesh never leak between its triangles.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include <glm/vec3.hpp>

namespace rtusim {

// Per-ray precomputation: the axis permutation and shear that map the ray to +z, and the
// origin's coordinates in permuted order.
struct WatertightRay {
  int kx = 0, ky = 1, kz = 2;
  float ox = 0.0f, oy = 0.0f, oz = 0.0f;  // origin[kx], origin[ky], origin[kz]
  float sx = 0.0f, sy = 0.0f, sz = 1.0f;
  float dx = 0.0f, dy = 0.0f, dz = 1.0f;  // dir[kx], dir[ky], dir[kz] (for the refinement)

  WatertightRay() = default;
  WatertightRay(const glm::vec3& o_vec, const glm::vec3& d_vec) {
    // Plain arrays: a glm::vec3 indexed by a run-time axis is a switch.
    const float o[3] = {o_vec.x, o_vec.y, o_vec.z}, d[3] = {d_vec.x, d_vec.y, d_vec.z};
    const float a[3] = {std::abs(d[0]), std::abs(d[1]), std::abs(d[2])};
    kz = (a[0] > a[1]) ? (a[0] > a[2] ? 0 : 2) : (a[1] > a[2] ? 1 : 2);
    kx = kz == 2 ? 0 : kz + 1;
    ky = kx == 2 ? 0 : kx + 1;
    if (d[kz] < 0.0f) std::swap(kx, ky);  // keep the winding of the permuted frame
    ox = o[kx];
    oy = o[ky];
    oz = o[kz];
    dx = d[kx];
    dy = d[ky];
    dz = d[kz];
#if defined(__SSE2__)
    // The three divisions as one (lane by lane the same quotients).
    float q[4];
    _mm_storeu_ps(q, _mm_div_ps(_mm_setr_ps(dx, dy, 1.0f, 1.0f), _mm_set1_ps(dz)));
    sx = q[0];
    sy = q[1];
    sz = q[2];
#else
    sx = dx / dz;
    sy = dy / dz;
    sz = 1.0f / dz;
#endif
  }
};

namespace watertight_detail {

// t is recomputed in double where |t| is below this many times its rounding-error bound.
constexpr float kRefineAbove = 1024.0f;

// gamma(n) of Higham / pbrt: bounds the relative error of n float roundings.
constexpr float gamma_f(int n) {
  constexpr float eps = 0.5f * 1.1920929e-7f;  // unit roundoff 2^-24
  return (n * eps) / (1.0f - n * eps);
}

// t of the ray through the triangle's plane, recomputed in double from the float inputs (all
// coordinates permuted like the ray's): (n . (p0 - o)) / (n . d). Returns a value <= 0 when the
// origin lies on the plane within the double computation's own error (the exact t is 0 there),
// or behind it.
[[gnu::noinline]] inline double refine_t(const WatertightRay& r, const float* v) {
  const double o[3] = {r.ox, r.oy, r.oz};
  const double d[3] = {r.dx, r.dy, r.dz};
  double p[3][3];
  for (int i = 0; i < 3; ++i) {
    p[i][0] = v[3 * i + r.kx];
    p[i][1] = v[3 * i + r.ky];
    p[i][2] = v[3 * i + r.kz];
  }
  const double e1[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
  const double e2[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
  const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                       e1[0] * e2[1] - e1[1] * e2[0]};
  const double w[3] = {p[0][0] - o[0], p[0][1] - o[1], p[0][2] - o[2]};
  const double num = n[0] * w[0] + n[1] * w[1] + n[2] * w[2];
  const double den = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
  // Differences of floats are exact in double; each product and sum adds a rounding of 2^-53,
  // and n's own rounding is below that of its terms: 1e-13 of the magnitudes covers all of it.
  const double num_err =
      1e-13 * (std::abs(n[0] * w[0]) + std::abs(n[1] * w[1]) + std::abs(n[2] * w[2]) +
               (std::abs(e1[1] * e2[2]) + std::abs(e1[2] * e2[1]) + std::abs(e1[2] * e2[0]) +
                std::abs(e1[0] * e2[2]) + std::abs(e1[0] * e2[1]) + std::abs(e1[1] * e2[0])) *
                   (std::abs(w[0]) + std::abs(w[1]) + std::abs(w[2])));
  if (std::abs(num) <= num_err || den == 0.0) return 0.0;
  return num / den;
}

// The test's last step where t needs no refinement: T = t * det against (0, t_max) scaled by
// det, then t = T / det itself; one branch for all of it. Sets t; false when out of range.
[[gnu::always_inline]] inline bool t_in_range(float T, float det, float inv, float t_max,
                                               float& t) {
  const float T_limit = t_max * det;
  const bool positive = det > 0.0f, negative = !positive;
  const bool outside = (positive & ((T <= 0.0f) | (T >= T_limit))) |
                       (negative & ((T >= 0.0f) | (T <= T_limit)));
  t = T * inv;
  return !(outside | !(t > 0.0f) | !(t < t_max));
}

#if defined(__SSE2__)
// Three floats in lanes 0..2 (lane 3 zero), the two lane rotations the barycentrics need, and
// one lane as a float.
inline __m128 lanes3(float a, float b, float c) { return _mm_setr_ps(a, b, c, 0.0f); }
inline __m128 rot201(__m128 x) { return _mm_shuffle_ps(x, x, _MM_SHUFFLE(3, 1, 0, 2)); }
inline __m128 rot120(__m128 x) { return _mm_shuffle_ps(x, x, _MM_SHUFFLE(3, 0, 2, 1)); }
template <int i>
inline float lane(__m128 x) {
  return _mm_cvtss_f32(_mm_shuffle_ps(x, x, _MM_SHUFFLE(3, 3, 3, i)));
}
#endif

// The scaled barycentrics U, V, W in double, rounded to float: used when one is exactly zero in
// float (an edge or vertex hit), so the sign decides which of the triangles sharing it is hit.
struct Barycentrics {
  float u, v, w;
};
inline Barycentrics exact_barycentrics(float Ax, float Ay, float Bx, float By, float Cx,
                                       float Cy) {
  return {static_cast<float>(double(Cx) * double(By) - double(Cy) * double(Bx)),
          static_cast<float>(double(Ax) * double(Cy) - double(Ay) * double(Cx)),
          static_cast<float>(double(Bx) * double(Ay) - double(By) * double(Ax))};
}

// The largest of three, as std::max({a, b, c}) picks it (the first of equals), without a loop.
inline float max3(float a, float b, float c) { return std::max(std::max(a, b), c); }

}  // namespace watertight_detail

// Intersects the triangle whose vertices are v[0..2], v[3..5], v[6..8] (x, y, z each) over t in
// (0, t_max). On a hit sets t and the barycentrics (u of the second vertex, v of the third)
// and returns true. Both faces count. `v` is anything indexable by 0..8 (a float array, or a
// view that reads the floats where they lie, so only the coordinates used are loaded).
template <class Vertices>
[[gnu::always_inline]] inline bool intersect_watertight(const WatertightRay& r, const Vertices& v,
                                                        float t_max, float& t, float& bu,
                                                        float& bv) {
#if defined(__SSE2__)
  // The same float operations as below, the three vertices in three lanes (lane 3 unused).
  using namespace watertight_detail;
  auto coord = [&](int k) { return lanes3(v[k], v[3 + k], v[6 + k]); };
  const __m128 Z = _mm_sub_ps(coord(r.kz), _mm_set1_ps(r.oz));
  const __m128 X = _mm_sub_ps(_mm_sub_ps(coord(r.kx), _mm_set1_ps(r.ox)),
                              _mm_mul_ps(_mm_set1_ps(r.sx), Z));
  const __m128 Y = _mm_sub_ps(_mm_sub_ps(coord(r.ky), _mm_set1_ps(r.oy)),
                              _mm_mul_ps(_mm_set1_ps(r.sy), Z));
  // U, V, W = Cx By - Cy Bx, Ax Cy - Ay Cx, Bx Ay - By Ax: lanes (2,0,1) times lanes (1,2,0).
  __m128 UVW = _mm_sub_ps(_mm_mul_ps(rot201(X), rot120(Y)), _mm_mul_ps(rot201(Y), rot120(X)));
  const float Ax = lane<0>(X), Bx = lane<1>(X), Cx = lane<2>(X);
  const float Ay = lane<0>(Y), By = lane<1>(Y), Cy = lane<2>(Y);
  const float Az = lane<0>(Z), Bz = lane<1>(Z), Cz = lane<2>(Z);
  const __m128 zero = _mm_setzero_ps();
  if (_mm_movemask_ps(_mm_cmpeq_ps(UVW, zero)) & 7) [[unlikely]] {
    const Barycentrics e = exact_barycentrics(Ax, Ay, Bx, By, Cx, Cy);
    UVW = lanes3(e.u, e.v, e.w);
  }
  // Mixed signs: outside (one branch: bit 3 of neg + 7 is set when one is negative).
  const int neg = _mm_movemask_ps(_mm_cmplt_ps(UVW, zero)) & 7;
  const int pos = _mm_movemask_ps(_mm_cmpgt_ps(UVW, zero)) & 7;
  if ((neg + 7) & (pos + 7) & 8) return false;
  const float U = lane<0>(UVW), V = lane<1>(UVW), W = lane<2>(UVW);
#else
  // Vertices relative to the ray origin, permuted and sheared into ray space.
  const float Az = v[r.kz] - r.oz, Bz = v[3 + r.kz] - r.oz, Cz = v[6 + r.kz] - r.oz;
  const float Ax = (v[r.kx] - r.ox) - r.sx * Az, Ay = (v[r.ky] - r.oy) - r.sy * Az;
  const float Bx = (v[3 + r.kx] - r.ox) - r.sx * Bz, By = (v[3 + r.ky] - r.oy) - r.sy * Bz;
  const float Cx = (v[6 + r.kx] - r.ox) - r.sx * Cz, Cy = (v[6 + r.ky] - r.oy) - r.sy * Cz;

  // Scaled barycentrics; recomputed in double when one is exactly zero (edge hits).
  float U = Cx * By - Cy * Bx, V = Ax * Cy - Ay * Cx, W = Bx * Ay - By * Ax;
  if ((U == 0.0f) | (V == 0.0f) | (W == 0.0f)) [[unlikely]] {
    const auto e = watertight_detail::exact_barycentrics(Ax, Ay, Bx, By, Cx, Cy);
    U = e.u;
    V = e.v;
    W = e.w;
  }
  // Mixed signs: outside (one branch for all six tests; which way it goes is hard to predict).
  if (((U < 0.0f) | (V < 0.0f) | (W < 0.0f)) & ((U > 0.0f) | (V > 0.0f) | (W > 0.0f))) return false;
#endif
  const float det = U + V + W;
  if (det == 0.0f) return false;  // ray in the triangle's plane, or a degenerate triangle

  // Scaled hit distance T = t * det.
  const float T = U * (r.sz * Az) + V * (r.sz * Bz) + W * (r.sz * Cz);
  const float inv = 1.0f / det;

  // t's rounding error (pbrt's conservative bound, PBR 3rd ed. 3.9.6). Where |t| is not at
  // least kRefineAbove times the bound, the float t may be far off in relative terms, a hit at
  // t ~ 0 from an origin on the plane may be spurious, or a genuine near hit may come out
  // negative: t is recomputed in double instead.
  using watertight_detail::gamma_f;
  using watertight_detail::max3;
  using watertight_detail::kRefineAbove;
  const float max_zt = max3(std::abs(r.sz * Az), std::abs(r.sz * Bz), std::abs(r.sz * Cz));
  const float max_xt = max3(std::abs(Ax), std::abs(Bx), std::abs(Cx));
  const float max_yt = max3(std::abs(Ay), std::abs(By), std::abs(Cy));
  const float delta_x = gamma_f(5) * (max_xt + max_zt), delta_y = gamma_f(5) * (max_yt + max_zt);
  const float delta_z = gamma_f(3) * max_zt;
  const float delta_e = 2.0f * (gamma_f(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
  const float max_e = max3(std::abs(U), std::abs(V), std::abs(W));
  const float delta_t =
      3.0f * (gamma_f(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * std::abs(inv);
  // T overflows float (from coordinates of ~1e12 on, its terms growing as their cube) while
  // t itself is fine: the double path too.
  if (!(std::abs(T) <= std::numeric_limits<float>::max()) |
      (std::abs(T * inv) <= kRefineAbove * delta_t)) [[unlikely]] {
    float xyz[9];
    for (int i = 0; i < 9; ++i) xyz[i] = v[i];
    const double td = watertight_detail::refine_t(r, xyz);
    t = static_cast<float>(td);
    if (!(td > 0.0) || !(t > 0.0f) || !(t < t_max)) return false;
  } else if (!watertight_detail::t_in_range(T, det, inv, t_max, t)) {
    return false;
  }
  bu = V * inv;
  bv = W * inv;
  return true;
}

// The same for a triangle given as three points.
[[gnu::always_inline]] inline bool intersect_watertight(const WatertightRay& r, const glm::vec3& a,
                                                        const glm::vec3& b, const glm::vec3& c,
                                                        float t_max, float& t, float& u,
                                                        float& v) {
  const float xyz[9] = {a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z};
  return intersect_watertight(r, xyz, t_max, t, u, v);
}

}  // namespace rtusim
