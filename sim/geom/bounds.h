// Axis-aligned bounding box in float, with the few operations the builder and tracer need.
#pragma once
#include <algorithm>
#include <limits>

#include <glm/vec3.hpp>

namespace rtusim {

struct Bounds3f {
  glm::vec3 min{std::numeric_limits<float>::infinity()};
  glm::vec3 max{-std::numeric_limits<float>::infinity()};

  bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
  void extend(const glm::vec3& p) {
    min = glm::vec3(std::min(min.x, p.x), std::min(min.y, p.y), std::min(min.z, p.z));
    max = glm::vec3(std::max(max.x, p.x), std::max(max.y, p.y), std::max(max.z, p.z));
  }
  void extend(const Bounds3f& b) {
    extend(b.min);
    extend(b.max);
  }
  glm::vec3 diagonal() const { return max - min; }
  float surface_area() const {
    if (empty()) return 0.0f;
    const glm::vec3 d = diagonal();
    return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
  }
  // Largest absolute coordinate: the scale used for scale-aware ray offsets.
  float max_abs_coord() const {
    float m = 0.0f;
    for (int a = 0; a < 3; ++a) m = std::max({m, std::abs(min[a]), std::abs(max[a])});
    return m;
  }
};

}  // namespace rtusim
