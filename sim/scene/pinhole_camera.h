// The contract's pinhole camera: primary ray for pixel (x, y), y = 0 the top row.
#pragma once
#include <cmath>
#include <string>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec3.hpp>
#include <glm/ext/vector_double3.hpp>

#include "geom/ray.h"
#include "scene/scene.h"

namespace rtusim {

// What makes `desc` unusable as a pinhole camera: `field` is the one at fault ("eye", "target",
// "up" or "vfov"; empty when the camera is fine) and `what` says why: eye equal to target, up
// zero or parallel to the view direction, a vector too long for single precision, a field of
// view outside (0, 180) degrees, or a non-finite number.
struct CameraProblem {
  std::string field, what;
};

inline CameraProblem camera_problem(const CameraDesc& desc) {
  const std::pair<const char*, glm::vec3> v[] = {
      {"eye", desc.eye}, {"target", desc.target}, {"up", desc.up}};
  for (const auto& [field, x] : v)
    if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z))
      return {field, std::string(field) + " is not finite"};
  const glm::vec3 f = desc.target - desc.eye;
  if (!(glm::length(f) > 0.0f)) return {"target", "target equals eye (no view direction)"};
  if (!std::isfinite(glm::length(f)))  // the farther of the two from the origin is at fault
    return {glm::length(glm::dvec3(desc.eye)) >= glm::length(glm::dvec3(desc.target)) ? "eye"
                                                                                        : "target",
            "eye and target are too far apart for single precision (over ~1e19)"};
  if (!(glm::length(desc.up) > 0.0f)) return {"up", "up is the zero vector"};
  if (!std::isfinite(glm::length(desc.up)))
    return {"up", "up is too long for single precision (over ~1e19)"};
  const glm::vec3 r = glm::cross(glm::normalize(f), glm::normalize(desc.up));
  if (!(glm::length(r) > 1e-6f))
    return {"up", "up is parallel to the view direction (target - eye)"};
  if (!(desc.vfov_deg > 0.0f && desc.vfov_deg < 180.0f))
    return {"vfov", "vertical field of view " + std::to_string(desc.vfov_deg) +
                        " degrees is not in (0, 180)"};
  return {};
}

class PinholeCamera {
 public:
  PinholeCamera(const CameraDesc& desc, int width, int height)
      : eye_(desc.eye), width_(width), height_(height) {
    f_ = glm::normalize(desc.target - desc.eye);
    r_ = glm::normalize(glm::cross(f_, desc.up));
    u_ = glm::cross(r_, f_);
    th_ = std::tan(glm::radians(desc.vfov_deg) / 2.0f);
    aspect_ = static_cast<float>(width) / static_cast<float>(height);
  }

  Ray generate(int x, int y) const {
    const float sx = (2.0f * (x + 0.5f) / width_ - 1.0f) * th_ * aspect_;
    const float sy = (1.0f - 2.0f * (y + 0.5f) / height_) * th_;
    Ray ray;
    ray.origin = eye_;
    ray.dir = glm::normalize(f_ + sx * r_ + sy * u_);
    return ray;
  }
  const glm::vec3& eye() const { return eye_; }

 private:
  glm::vec3 eye_, f_, r_, u_;
  float th_ = 1.0f, aspect_ = 1.0f;
  int width_, height_;
};

}  // namespace rtusim
