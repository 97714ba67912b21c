// Self-intersection avoidance: Wächter & Binder, "A Fast and Robust Method for Avoiding
// Self-Intersection" (Ray Tracing Gems, ch. 6). Moves a hit point off its surface by a few
// ulps of its coordinates; near the origin, where ulps vanish, by a fixed fraction of the
// scene's scale (the chapter's constants are for scenes of unit size, so both thresholds are
// multiplied by the scene's largest coordinate: a 7 mm scene gets 7 mm-sized offsets).
#pragma once
#include <bit>
#include <cmath>
#include <cstdint>

#include <glm/vec3.hpp>

namespace rtusim {

class RayOffset {
 public:
  explicit RayOffset(float scene_scale) {
    const float s = scene_scale > 0.0f && std::isfinite(scene_scale) ? scene_scale : 1.0f;
    origin_ = s / 32.0f;
    float_scale_ = s / 65536.0f;
  }

  // `p` moved off the surface along `n` (n points to the side the new ray leaves from).
  glm::vec3 offset(const glm::vec3& p, const glm::vec3& n) const {
    glm::vec3 out;
    for (int a = 0; a < 3; ++a) {
      const int32_t of_i = static_cast<int32_t>(kIntScale * n[a]);
      const int32_t bits = std::bit_cast<int32_t>(p[a]);
      const float p_i = std::bit_cast<float>(bits + (p[a] < 0.0f ? -of_i : of_i));
      out[a] = std::abs(p[a]) < origin_ ? p[a] + float_scale_ * n[a] : p_i;
    }
    return out;
  }

 private:
  static constexpr float kIntScale = 256.0f;
  float origin_, float_scale_;
};

}  // namespace rtusim
