// Every run key in one place: name, type, default and range.
#include "config/run_config.h"

#include <cstdlib>
#include <filesystem>

#include "cache/cache_config.h"
#include "layout/layout.h"
#include "tier/interleaved_backend.h"
#include "util/error.h"

#ifndef RTUSIM_SOURCE_DIR
#define RTUSIM_SOURCE_DIR "."
#endif

namespace rtusim {

std::string scenes_dir() {
  if (const char* env = std::getenv("RTUSIM_SCENES"); env && *env) return env;
  return (std::filesystem::path(RTUSIM_SOURCE_DIR) / ".." / "shared" / "scenes")
      .lexically_normal()
      .string();
}

std::string resolve_scene_path(const std::string& path, const std::string& base_dir) {
  if (path.rfind("builtin:", 0) == 0) return path;
  for (const std::string prefix : {"$RTUSIM_SCENES", "${RTUSIM_SCENES}"})
    if (path.rfind(prefix, 0) == 0) return scenes_dir() + path.substr(prefix.size());
  const std::filesystem::path p(path);
  if (p.is_absolute() || base_dir.empty()) return path;
  return (std::filesystem::path(base_dir) / p).lexically_normal().string();
}

RunConfig load_run_config(const std::string& path, const std::vector<std::string>& overrides) {
  ConfigReader r = ConfigReader::from_file(path);
  for (const auto& o : overrides) r.apply_override(o);

  RunConfig c;
  c.origin = path;

  // [scene]
  c.scene.path = r.get_string("scene.path", "builtin:cornell");
  c.scene.resolved = resolve_scene_path(c.scene.path, r.base_dir());
  c.scene.camera = r.get_string("scene.camera", "");

  // [camera]: an explicit pinhole camera (all of eye, target; up and vfov default)
  const auto eye = r.get_vec3("camera.eye"), target = r.get_vec3("camera.target");
  const auto up = r.get_vec3("camera.up");
  const bool any_camera = eye || target || up || r.has("camera.vfov");
  if (any_camera) {
    const double vfov = r.get_float("camera.vfov", 45.0, 1e-3, 179.0);
    if (!eye || !target) {
      throw InputError(path + ": camera: camera.eye and camera.target are both required when "
                       "any camera.* key is given");
    }
    if (!c.scene.camera.empty())
      throw InputError(path + ": camera: give scene.camera or camera.*, not both");
    c.camera = CameraDesc{"config", *eye, *target, up.value_or(glm::vec3(0, 1, 0)),
                          static_cast<float>(vfov)};
  }

  // [image]
  c.image.width = static_cast<int>(r.get_int("image.width", 256, 1, 16384));
  c.image.height = static_cast<int>(r.get_int("image.height", 256, 1, 16384));
  c.image.write_png = r.get_bool("image.png", true);
  c.image.heatmaps = r.get_bool("image.heatmaps", true);

  // [tracer]
  c.tracer.max_depth = static_cast<int>(r.get_int("tracer.max_depth", 4, 0, 16));
  c.tracer.order = r.get_string("tracer.ray_order", "recursive", {"recursive", "wavefront"}) ==
                           "wavefront"
                       ? RayOrder::kWavefront
                       : RayOrder::kRecursive;
  c.tracer.mirror_threshold =
      static_cast<float>(r.get_float("tracer.mirror_threshold", 0.5, 0.0, 1.0));
  c.tracer.ambient = static_cast<float>(r.get_float("tracer.ambient", 0.1, 0.0, 1e6));
  if (auto bg = r.get_vec3("tracer.background")) c.tracer.background = *bg;
  c.tracer.headlight = r.get_bool("tracer.headlight", true);

  // [kdtree]: SAH cost model and limits
  c.kdtree.traversal_cost = static_cast<float>(r.get_float("kdtree.traversal_cost", 1.0, 1e-6, 1e6));
  c.kdtree.isect_cost = static_cast<float>(r.get_float("kdtree.isect_cost", 80.0, 1e-6, 1e6));
  c.kdtree.empty_bonus = static_cast<float>(r.get_float("kdtree.empty_bonus", 0.5, 0.0, 0.99));
  c.kdtree.max_depth = static_cast<int>(r.get_int("kdtree.max_depth", -1, -1, 60));
  c.kdtree.leaf_prims = static_cast<int>(r.get_int("kdtree.leaf_prims", 1, 1, 1 << 20));

  // [layout]
  c.layouts = r.get_string_list("layout.kind", {"dfl"}, layout_kinds());

  // [l1], [dcache]: the caches in front of DRAM
  c.caches = read_fetch_cache_params(r);

  // [sim], [report]: the tier; the cycle tier's own keys (read whatever the tier, so they are
  // validated and in the effective config), l1.model and sim.vcd among them
  c.sim.tier_name = r.get_string("sim.tier", "functional", {"functional", "cycle", "rtl"});
  c.sim.tier = c.sim.tier_name == "cycle" ? Tier::kCycle
               : c.sim.tier_name == "rtl" ? Tier::kRtl
                                          : Tier::kFunctional;
  c.sim.frames_per_second = r.get_float("report.frames_per_second", 30.0, 1e-6, 1e6);
  c.cycle = read_cycle_params(r);
  if (c.sim.tier == Tier::kRtl) {
    // The rtl tier is the cycle tier with the Verilated node L1.
    if (r.has("l1.model") && c.cycle.node_l1_model != "rtl")
      throw InputError(path + ": l1.model: sim.tier = \"rtl\" uses the RTL L1, not \"" +
                       c.cycle.node_l1_model + "\"");
    c.cycle.node_l1_model = "rtl";
    try {
      c.cycle.finish();
    } catch (const InputError& e) {
      throw InputError(path + ": " + e.what());
    }
  }
  if (c.cycle.node_l1_model == "rtl" && c.sim.tier == Tier::kFunctional)
    throw InputError(path + ": l1.model: \"rtl\" needs sim.tier = \"cycle\" or \"rtl\"");

  c.sample = read_sample_params(r);
  c.functional_rays_in_flight = read_functional_rays_in_flight(r);

  r.reject_unknown_keys();
  c.effective = r.effective();
  return c;
}

}  // namespace rtusim
