// glTF 2.0 (.gltf / .glb) scene loading through tinygltf; textures are never decoded.
#pragma once
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
Scene load_gltf(const std::string& path);

}  // namespace rtusim
