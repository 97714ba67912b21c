// Parameters of the host Whitted tracer, and the tracer.* keys they come from (declared in
// tracer_params.cpp).
#pragma once
#include <glm/vec3.hpp>

namespace rtusim {

enum class RayOrder {
  kRecursive,  // the study's order: each pixel's ray tree depth first, one ray at a time
  kWavefront,  // generation by generation over the whole frame
};

struct TracerParams {
  int max_depth = 4;               // secondary bounces after the primary hit
  RayOrder order = RayOrder::kRecursive;
  float mirror_threshold = 0.5f;   // metallic at or above this reflects
  float ambient = 0.1f;            // ambient term times base colour
  glm::vec3 background{0.5f, 0.5f, 1.0f};
  bool headlight = true;           // a point light at the eye when the scene has none
};

class ConfigReader;
// Reads tracer.* (errors name the key and where it was set).
TracerParams read_tracer_params(ConfigReader& r);

}  // namespace rtusim
