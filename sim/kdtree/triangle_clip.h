// Perfect-split support: the bounds of the part of a triangle inside an axis-aligned box.
#pragma once
#include <array>

#include <glm/vec3.hpp>

#include "geom/bounds.h"

namespace rtusim {

// Bounds of triangle `v` clipped to `box` (Sutherland-Hodgman in double precision, rounded
// outwards to float, then clamped into `box`). Returns an empty Bounds3f when nothing of the
// triangle lies inside the box; callers that know the triangle overlaps must fall back.
Bounds3f clip_triangle_bounds(const std::array<glm::vec3, 3>& v, const Bounds3f& box);

// Intersection of two boxes; each axis is clamped into `box` so that the result is never empty
// when `box` is not (a point on the nearest face stands in for a miss caused by rounding).
Bounds3f clamp_bounds_into(const Bounds3f& b, const Bounds3f& box);

}  // namespace rtusim
