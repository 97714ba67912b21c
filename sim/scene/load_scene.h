// Scene by name: "builtin:NAME" or a glTF file path.
#pragma once
#include <string>

#include "scene/builtin_scene.h"
#include "scene/gltf_loader.h"

namespace rtusim {

inline Scene load_scene(const std::string& resolved_path) {
  if (resolved_path.rfind("builtin:", 0) == 0) return make_builtin_scene(resolved_path.substr(8));
  return load_gltf(resolved_path);
}

}  // namespace rtusim
