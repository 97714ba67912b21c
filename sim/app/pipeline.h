// What every command does first: config -> scene -> camera -> kd-tree -> memory images.
#pragma once
#include <string>
#include <vector>

#include "app/run_config.h"
#include "kdtree/kd_tree.h"
#include "layout/memory_image.h"
#include "scene/scene.h"

namespace rtusim {

struct Prepared {
  RunConfig config;
  Scene scene;
  CameraDesc camera;
  KdTree tree;
  std::vector<MemoryImage> images;  // one per layout.kind, in config order
  double scene_load_seconds = 0.0;
};

// The config's scene (scene.path), loaded. Throws InputError naming scene.path and where it
// was set on a scene that does not load.
Scene load_config_scene(const RunConfig& config);

// The camera the config asks for in `scene` (select_camera), checked (camera_problem). Throws
// InputError naming the key at fault and where it was set.
CameraDesc checked_camera(const RunConfig& config, const Scene& scene);

// Throws InputError on bad input (config, scene, camera).
Prepared prepare_run(const std::string& config_path, const std::vector<std::string>& overrides);

// The camera the config asks for: camera.*, else scene.camera by node name, else the scene's
// first camera node. Throws InputError naming the key when none fits.
CameraDesc select_camera(const RunConfig& config, const Scene& scene);

}  // namespace rtusim
