// Watertight ray/triangle intersection (Woop, Benthin, Wald, JCGT 2013): rays through shared
// edges and vertices of a closed mesh never leak between its triangles.
#pragma once
#include <cmath>
#include <utility>

#include <glm/vec3.hpp>

namespace rtusim {

// Per-ray precomputation: the axis permutation and shear that map the ray to +z, and the
// origin's coordinates in permuted order.
struct WatertightRay {
  int kx = 0, ky = 1, kz = 2;
  float ox = 0.0f, oy = 0.0f, oz = 0.0f;  // origin[kx], origin[ky], origin[kz]
  float sx = 0.0f, sy = 0.0f, sz = 1.0f;

  WatertightRay() = default;
  WatertightRay(const glm::vec3& o, const glm::vec3& d) {
    const glm::vec3 a(std::abs(d.x), std::abs(d.y), std::abs(d.z));
    kz = (a.x > a.y) ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (d[kz] < 0.0f) std::swap(kx, ky);  // keep the winding of the permuted frame
    ox = o[kx];
    oy = o[ky];
    oz = o[kz];
    sx = d[kx] / d[kz];
    sy = d[ky] / d[kz];
    sz = 1.0f / d[kz];
  }
};

// Intersects the triangle whose vertices are v[0..2], v[3..5], v[6..8] (x, y, z each) over t in
// (0, t_max). On a hit sets t and the barycentrics (u of the second vertex, v of the third)
// and returns true. Both faces count.
[[gnu::always_inline]] inline bool intersect_watertight(const WatertightRay& r, const float* v,
                                                        float t_max, float& t, float& bu,
                                                        float& bv) {
  // Vertices relative to the ray origin, permuted and sheared into ray space.
  const float Az = v[r.kz] - r.oz, Bz = v[3 + r.kz] - r.oz, Cz = v[6 + r.kz] - r.oz;
  const float Ax = (v[r.kx] - r.ox) - r.sx * Az, Ay = (v[r.ky] - r.oy) - r.sy * Az;
  const float Bx = (v[3 + r.kx] - r.ox) - r.sx * Bz, By = (v[3 + r.ky] - r.oy) - r.sy * Bz;
  const float Cx = (v[6 + r.kx] - r.ox) - r.sx * Cz, Cy = (v[6 + r.ky] - r.oy) - r.sy * Cz;

  // Scaled barycentrics; recomputed in double when one is exactly zero (edge hits).
  float U = Cx * By - Cy * Bx, V = Ax * Cy - Ay * Cx, W = Bx * Ay - By * Ax;
  if (U == 0.0f || V == 0.0f || W == 0.0f) [[unlikely]] {
    U = static_cast<float>(double(Cx) * double(By) - double(Cy) * double(Bx));
    V = static_cast<float>(double(Ax) * double(Cy) - double(Ay) * double(Cx));
    W = static_cast<float>(double(Bx) * double(Ay) - double(By) * double(Ax));
  }
  if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return false;
  const float det = U + V + W;
  if (det == 0.0f) return false;  // ray in the triangle's plane, or a degenerate triangle

  // Scaled hit distance, compared before the division.
  const float T = U * (r.sz * Az) + V * (r.sz * Bz) + W * (r.sz * Cz);
  if (det > 0.0f ? (T <= 0.0f || T >= t_max * det) : (T >= 0.0f || T <= t_max * det))
    return false;
  const float inv = 1.0f / det;
  t = T * inv;
  if (!(t > 0.0f) || !(t < t_max)) return false;
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
