// The loaded scene: world-space triangles, materials, point lights and cameras.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "geom/bounds.h"

namespace rtusim {

// A glTF metallic-roughness material reduced to the factors a Whitted tracer uses.
struct Material {
  std::string name;
  glm::vec3 base_color{1.0f};
  float metallic = 1.0f;   // glTF default
  float roughness = 1.0f;  // glTF default
  glm::vec3 emissive{0.0f};
  float transmission = 0.0f;  // KHR_materials_transmission
  float ior = 1.5f;           // KHR_materials_ior
};

struct PointLight {
  std::string name;
  glm::vec3 position{0.0f};
  glm::vec3 color{1.0f};
  float intensity = 1.0f;
};

// A pinhole camera as the contract defines it (eye, target, up, vertical field of view).
struct CameraDesc {
  std::string name;
  glm::vec3 eye{0.0f, 0.0f, 1.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float vfov_deg = 45.0f;
};

struct Scene {
  std::string source;  // file path, or "builtin:<name>"
  // Geometry. Triangle id i is triangles[i]; ids follow the contract's load order.
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // per vertex; (0,0,0) where the mesh had no NORMAL
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<uint32_t> triangle_material;  // per triangle, index into materials
  std::vector<Material> materials;          // never empty once loaded (a default is added)
  std::vector<PointLight> lights;
  std::vector<CameraDesc> cameras;          // named camera nodes, in node order

  uint32_t triangle_count() const { return static_cast<uint32_t>(triangles.size()); }
  std::array<glm::vec3, 3> vertices(uint32_t tri) const {
    const auto& t = triangles[tri];
    return {positions[t[0]], positions[t[1]], positions[t[2]]};
  }
  Bounds3f bounds() const {
    Bounds3f b;
    for (const auto& t : triangles)
      for (uint32_t i : t) b.extend(positions[i]);
    return b;
  }
  // Bytes of geometry the host keeps for this scene (reported in the stats).
  uint64_t geometry_bytes() const {
    return positions.size() * sizeof(glm::vec3) + normals.size() * sizeof(glm::vec3) +
           triangles.size() * sizeof(triangles[0]) + triangle_material.size() * sizeof(uint32_t);
  }
};

}  // namespace rtusim
