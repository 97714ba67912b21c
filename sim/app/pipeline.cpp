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

namespace {

CameraDesc scene_camera(const RunConfig& config, const Scene& scene) {
  if (!config.scene.camera.empty()) {
    const CameraDesc* found = nullptr;
    int count = 0;
    for (const auto& c : scene.cameras)
      if (c.name == config.scene.camera && count++ == 0) found = &c;
    if (count > 1)  // which one is meant is not known: not the first silently
      throw InputError(config.origins.at("scene.camera") + ": scene.camera: " +
                       std::to_string(count) + " camera nodes are named '" + config.scene.camera +
                       "' in " + scene.source);
    if (found) return *found;
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

}  // namespace

CameraDesc select_camera(const RunConfig& config, const Scene& scene) {
  if (config.camera) return *config.camera;
  CameraDesc c = scene_camera(config, scene);
  if (config.scene_vfov_deg) c.vfov_deg = *config.scene_vfov_deg;
  return c;
}

Scene load_config_scene(const RunConfig& config) {
  try {
    return load_scene(config.scene.resolved);
  } catch (const InputError& e) {
    throw InputError(config.origins.at("scene.path") + ": scene.path: " + e.what());
  }
}

CameraDesc checked_camera(const RunConfig& config, const Scene& scene) {
  const CameraDesc camera = select_camera(config, scene);
  // A camera of the config is named by its key at fault; a scene's by scene.camera.
  if (const CameraProblem bad = camera_problem(camera); !bad.field.empty()) {
    if (config.camera) {
      const std::string key = "camera." + bad.field;
      throw InputError(config.origins.at(key) + ": " + key + ": " + bad.what);
    }
    throw InputError(config.origins.at("scene.camera") + ": scene.camera: " + camera.name +
                     ": " + bad.what);
  }
  return camera;
}

Prepared prepare_run(const std::string& config_path, const std::vector<std::string>& overrides) {
  Prepared p;
  p.config = load_run_config(config_path, overrides);
  const auto t0 = std::chrono::steady_clock::now();
  p.scene = load_config_scene(p.config);
  p.scene_load_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  p.camera = checked_camera(p.config, p.scene);
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
