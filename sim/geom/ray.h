// Rays and hit records: the unit of work between the tracer and traversal.
#pragma once
#include <cstdint>
#include <limits>

#include <glm/vec3.hpp>

namespace rtusim {

struct Ray {
  glm::vec3 origin{0.0f};
  glm::vec3 dir{0.0f, 0.0f, 1.0f};  // need not be normalised; t is in units of |dir|
  float t_max = std::numeric_limits<float>::infinity();
};

constexpr uint32_t kNoTriangle = 0xffffffffu;

struct Hit {
  float t = std::numeric_limits<float>::infinity();
  uint32_t triangle = kNoTriangle;  // scene triangle id (load order)
  float u = 0.0f, v = 0.0f;         // barycentrics of vertex 1 and vertex 2
  bool valid() const { return triangle != kNoTriangle; }
};

}  // namespace rtusim
