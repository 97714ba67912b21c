// The contract's pinhole camera: primary ray for pixel (x, y), y = 0 the top row.
#pragma once
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec3.hpp>

#include "geom/ray.h"
#include "scene/scene.h"

namespace rtusim {

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
