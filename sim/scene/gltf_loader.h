// glTF 2.0 (.gltf / .glb) scene loading through tinygltf; textures are never decoded.
#pragma once
#include <string>

#include "scene/scene.h"

namespace rtusim {

// Loads the default scene (or scene 0) of a glTF file into world-space triangles in the
// contract's load order. Throws InputError naming the file and what is wrong.
Scene load_gltf(const std::string& path);

}  // namespace rtusim
