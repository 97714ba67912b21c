// Built-in procedural scenes, so the default run needs no external file.
#pragma once
#include <string>

#include "scene/scene.h"

namespace rtusim {

// "cornell": a Cornell-style room with a mirror object and a glass object (a few thousand
// triangles), one point light and a camera named "default". Throws InputError on unknown names.
Scene make_builtin_scene(const std::string& name);

}  // namespace rtusim
