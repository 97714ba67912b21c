// Shared set-up of a run.
#include "app/pipeline.h"

#include <chrono>

#include "app/profile_training.h"
#include "kdtree/sah_builder.h"
#include "layout/layout.h"
#include "layout/profile_layout.h"
#include "scene/load_scene.h"
#include "scene/pinhole_camera.h"
#include "util/error.h"

namespace rtusim {

CameraDesc select_camera(const RunConfig& config, const Scene& scene) {
  if (config.camera) return *config.camera;
  if (!config.scene.camera.empty()) {
    for (const auto& c : scene.cameras)
      if (c.name == config.scene.camera) return c;
    std::string known;
    for (const auto& c : scene.cameras) known += (known.empty() ? "" : ", ") + c.name;
    throw InputError(config.origins.at("scene.camera") + ": scene.camera: no camera node '" +
                     config.scene.camera + "' in " + scene.source + " (cameras: " +
                     (known.empty() ? "none" : known) + ")");
  }
  if (!scene.cameras.empty()) return scene.cameras.front();
  throw InputError(config.origins.at("scene.path") + ": camera: " + scene.source +
                   " has no camera; set scene.camera or camera.eye/camera.target");
}

Prepared prepare_run(const std::string& config_path, const std::vector<std::string>& overrides) {
  Prepared p;
  p.config = load_run_config(config_path, overrides);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    p.scene = load_scene(p.config.scene.resolved);
  } catch (const InputError& e) {
    throw InputError(p.config.origins.at("scene.path") + ": scene.path: " + e.what());
  }
  p.scene_load_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  p.camera = select_camera(p.config, p.scene);
  if (const std::string why = camera_problem(p.camera); !why.empty())
    throw InputError(p.config.origins.at(p.config.camera ? "camera" : "scene.camera") + ": " +
                     (p.config.camera ? "camera" : "scene.camera") + ": " + why);
  p.tree = build_sah_kd_tree(p.scene, p.config.kdtree);
  for (const auto& kind : p.config.layout.kinds) {
    const std::unique_ptr<Layout> layout = make_layout(kind);
    if (auto* profile = dynamic_cast<ProfileLayout*>(layout.get()))
      profile->set_visits(profile_training_visits(p.tree, p.scene, p.camera, p.config.tracer));
    p.images.push_back(layout->build_image(p.tree, p.scene));
  }
  return p;
}

}  // namespace rtusim
