// glTF 2.0 (.gltf / .glb) scene loading through tinygltf; textures are never decoded.
#pragma once
#include <cstdint>
#include <string>

#include "scene/scene.h"

namespace rtusim {

// Loads the default scene (or scene 0) of a glTF file into world-space triangles in the
// contract's load order. Throws InputError naming the file and what is wrong.
// - Strips and fans follow the glTF spec: strip {v_i, v_i+1+i%2, v_i+2-i%2}, fan {v_i+1, v_i+2, v_0}.
// - Under a mirroring node transform (negative determinant) the last two indices of each
//   triangle are swapped, so geometric normals keep their outward side.
// - Materials keep their glTF indices; a glTF default material is appended when needed.
// - Only KHR_lights_punctual point lights are loaded (spot and directional are skipped);
//   cameras are perspective camera nodes in traversal order, named after the node.
// Resource limits, checked before the memory is taken (each a clear InputError).
struct SceneLimits {
  uint64_t max_scene_bytes = uint64_t{16} << 30;  // file size, and geometry once flattened
  int max_json_depth = 128;                       // arrays/objects inside each other
  // The defaults, with max_scene_bytes from RTUSIM_MAX_SCENE_MB when set.
  static SceneLimits from_environment();
};

Scene load_gltf(const std::string& path, const SceneLimits& limits = SceneLimits::from_environment());

}  // namespace rtusim
