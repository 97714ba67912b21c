// Watertight ray/triangle intersection (Woop, Benthin, Wald, JCGT 2013): rays through shared
// edges and vertices of a closed mesh never leak between its triangles.
#pragma once
#include <cmath>
#include <utility>

#include <glm/vec3.hpp>

namespace rtusim {

// Per-ray precomputation: the axis permutation and shear that map the ray to +z.
struct WatertightRay {
  glm::vec3 org;
  int kx = 0, ky = 1, kz = 2;
  float sx = 0.0f, sy = 0.0f, sz = 1.0f;

  explicit WatertightRay(const glm::vec3& o, const glm::vec3& d) : org(o) {
    const glm::vec3 a(std::abs(d.x), std::abs(d.y), std::abs(d.z));
    kz = (a.x > a.y) ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (d[kz] < 0.0f) std::swap(kx, ky);  // keep the winding of the permuted frame
    sx = d[kx] / d[kz];
    sy = d[ky] / d[kz];
    sz = 1.0f / d[kz];
  }
};

// Intersects triangle (a, b, c) over t in (0, t_max). On a hit sets t and the barycentrics
// (u of b, v of c) and returns true. Both faces count.
inline bool intersect_watertight(const WatertightRay& r, const glm::vec3& a, const glm::vec3& b,
                                 const glm::vec3& c, float t_max, float& t, float& u, float& v) {
  // Vertices relative to the ray origin, sheared into ray space.
  const glm::vec3 A = a - r.org, B = b - r.org, C = c - r.org;
  const float Ax = A[r.kx] - r.sx * A[r.kz], Ay = A[r.ky] - r.sy * A[r.kz];
  const float Bx = B[r.kx] - r.sx * B[r.kz], By = B[r.ky] - r.sy * B[r.kz];
  const float Cx = C[r.kx] - r.sx * C[r.kz], Cy = C[r.ky] - r.sy * C[r.kz];

  // Scaled barycentrics; recomputed in double when one is exactly zero (edge hits).
  float U = Cx * By - Cy * Bx, V = Ax * Cy - Ay * Cx, W = Bx * Ay - By * Ax;
  if (U == 0.0f || V == 0.0f || W == 0.0f) {
    U = static_cast<float>(double(Cx) * double(By) - double(Cy) * double(Bx));
    V = static_cast<float>(double(Ax) * double(Cy) - double(Ay) * double(Cx));
    W = static_cast<float>(double(Bx) * double(Ay) - double(By) * double(Ax));
  }
  if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return false;
  const float det = U + V + W;
  if (det == 0.0f) return false;  // ray in the triangle's plane, or a degenerate triangle

  // Scaled hit distance, compared before the division.
  const float Az = r.sz * A[r.kz], Bz = r.sz * B[r.kz], Cz = r.sz * C[r.kz];
  const float T = U * Az + V * Bz + W * Cz;
  if (det > 0.0f ? (T <= 0.0f || T >= t_max * det) : (T >= 0.0f || T <= t_max * det))
    return false;
  const float inv = 1.0f / det;
  t = T * inv;
  if (!(t > 0.0f) || !(t < t_max)) return false;
  u = V * inv;
  v = W * inv;
  return true;
}

}  // namespace rtusim
