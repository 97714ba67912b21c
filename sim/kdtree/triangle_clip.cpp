// Triangle-against-box clipping for the SAH builder's perfect splits.
#include "kdtree/triangle_clip.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

namespace rtusim {
namespace {

// A convex polygon of at most 3 + 6 vertices (one extra vertex per clipping plane).
struct ClipPolygon {
  std::array<glm::dvec3, 12> v;
  int n = 0;
};

// Keeps the part of `in` with sign * (p[axis] - plane) >= 0. Crossing points get the plane
// coordinate exactly so they never stray outside the box on that axis.
void clip_to_plane(const ClipPolygon& in, ClipPolygon& out, int axis, double plane, double sign) {
  out.n = 0;
  for (int i = 0; i < in.n; ++i) {
    const glm::dvec3& a = in.v[i];
    const glm::dvec3& b = in.v[(i + 1) % in.n];
    const double da = sign * (a[axis] - plane);
    const double db = sign * (b[axis] - plane);
    if (da >= 0.0) out.v[out.n++] = a;
    if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) {
      const double t = da / (da - db);
      glm::dvec3 p = a + t * (b - a);
      p[axis] = plane;
      out.v[out.n++] = p;
    }
  }
}

// Largest float <= d and smallest float >= d.
float round_down(double d) {
  float f = static_cast<float>(d);
  if (static_cast<double>(f) > d) f = std::nextafter(f, -INFINITY);
  return f;
}
float round_up(double d) {
  float f = static_cast<float>(d);
  if (static_cast<double>(f) < d) f = std::nextafter(f, INFINITY);
  return f;
}

}  // namespace

Bounds3f clip_triangle_bounds(const std::array<glm::vec3, 3>& v, const Bounds3f& box) {
  ClipPolygon a, b;
  a.n = 3;
  for (int i = 0; i < 3; ++i) a.v[i] = glm::dvec3(v[i]);
  // Six half-spaces: min face then max face of each axis.
  for (int axis = 0; axis < 3; ++axis) {
    clip_to_plane(a, b, axis, box.min[axis], 1.0);
    clip_to_plane(b, a, axis, box.max[axis], -1.0);
    if (a.n == 0) return Bounds3f{};
  }
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (int i = 0; i < a.n; ++i) {
    lo = glm::min(lo, a.v[i]);
    hi = glm::max(hi, a.v[i]);
  }
  Bounds3f out;
  for (int axis = 0; axis < 3; ++axis) {
    out.min[axis] = round_down(lo[axis]);
    out.max[axis] = round_up(hi[axis]);
  }
  return clamp_bounds_into(out, box);
}

Bounds3f clamp_bounds_into(const Bounds3f& b, const Bounds3f& box) {
  Bounds3f out;
  for (int axis = 0; axis < 3; ++axis) {
    const float lo = std::clamp(b.min[axis], box.min[axis], box.max[axis]);
    const float hi = std::clamp(b.max[axis], box.min[axis], box.max[axis]);
    out.min[axis] = std::min(lo, hi);
    out.max[axis] = std::max(lo, hi);
  }
  return out;
}

}  // namespace rtusim
