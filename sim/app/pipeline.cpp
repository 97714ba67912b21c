// Shared set-up of a run.
#include "app/pipeline.h"

#include <chrono>

#include "kdtree/sah_builder.h"
#include "layout/layout.h"
#include "scene/load_scene.h"
#include "util/error.h"

namespace rtusim {

CameraDesc select_camera(const RunConfig& config, const Scene& scene) {
  if (config.camera) return *config.camera;
  if (!config.scene.camera.empty()) {
    for (const auto& c : scene.cameras)
      if (c.name == config.scene.camera) return c;
    std::string known;
    for (const auto& c : scene.cameras) known += (known.empty() ? "" : ", ") + c.name;
    throw InputError(config.origin + ": scene.camera: no camera node '" + config.scene.camera +
                     "' in " + scene.source + " (cameras: " + (known.empty() ? "none" : known) +
                     ")");
  }
  if (!scene.cameras.empty()) return scene.cameras.front();
  throw InputError(config.origin + ": camera: " + scene.source +
                   " has no camera; set scene.camera or camera.eye/camera.target");
}

Prepared prepare_run(const std::string& config_path, const std::vector<std::string>& overrides) {
  Prepared p;
  p.config = load_run_config(config_path, overrides);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    p.scene = load_scene(p.config.scene.resolved);
  } catch (const InputError& e) {
    throw InputError(config_path + ": scene.path: " + e.what());
  }
  p.scene_load_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  p.camera = select_camera(p.config, p.scene);
  p.tree = build_sah_kd_tree(p.scene, p.config.kdtree);
  for (const auto& kind : p.config.layout.kinds)
    p.images.push_back(make_layout(kind)->build_image(p.tree, p.scene));
  return p;
}

}  // namespace rtusim
