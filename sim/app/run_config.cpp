// The run config: the keys of scene, camera, image and report (the other subtrees are declared
// by their parts), read in one pass.
#include "app/run_config.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "config/param.h"
#include "kdtree/sah_builder.h"
#include "layout/layout.h"
#include "tier/tier.h"
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
    if (path.rfind(prefix, 0) == 0 &&
        (path.size() == prefix.size() || path[prefix.size()] == '/'))  // not $RTUSIM_SCENESX
      return scenes_dir() + path.substr(prefix.size());
  const std::filesystem::path p(path);
  if (p.is_absolute() || base_dir.empty()) return path;
  return (std::filesystem::path(base_dir) / p).lexically_normal().string();
}

namespace {

const ImageParams kImage;
const ReportParams kReport;
const StringParam kScenePath("scene.path", "builtin:cornell", {}, "path",
                             "glTF file ($RTUSIM_SCENES/..., relative to the config) or "
                             "builtin:NAME");
const StringParam kSceneCamera("scene.camera", "", {}, "",
                               "glTF camera node name (\"\": camera.*, else the first camera)");
const Vec3Param kEye("camera.eye", std::nullopt, "scene units",
                     "pinhole camera position (with target)");
const Vec3Param kTarget("camera.target", std::nullopt, "scene units", "point the camera looks at");
const Vec3Param kUp("camera.up", glm::vec3(0, 1, 0), "",
                    "camera up direction (with camera.eye and camera.target)");
const FloatParam kVfov("camera.vfov", 45.0, 1e-3, 179.0, "degrees",
                       "vertical field of view (alone: of the scene's camera)");
const IntParam kWidth("image.width", kImage.width, 1, 16384, "pixels", "image width");
const IntParam kHeight("image.height", kImage.height, 1, 16384, "pixels", "image height");
const BoolParam kPng("image.png", kImage.write_png, "write image.png, the rendered frame");
const BoolParam kHeatmaps("image.heatmaps", kImage.heatmaps,
                          "write per-layout DRAM-traffic heatmaps (functional tier)");
const FloatParam kFramesPerSecond("report.frames_per_second", kReport.frames_per_second, 1e-6,
                                  1e6, "frames/s", "frame rate of the GB/s figures");

}  // namespace

FetchCacheParams RunConfig::fetch_caches() const {
  FetchCacheParams p;
  p.node_l1 = l1.params.cache;
  if (dcache.enable) p.data_cache = dcache.params.cache;
  p.dram_burst_bytes = dram.burst_bytes();
  return p;
}

CycleParams RunConfig::cycle() const {
  return make_cycle_params(sim.clock_mhz, unit, l1, dcache, dram, sim.vcd_path);
}

std::string layout_vcd_path(const std::string& vcd_path, const std::string& layout) {
  const std::filesystem::path vcd(vcd_path);
  return (vcd.parent_path() / (vcd.stem().string() + "_" + layout + vcd.extension().string()))
      .string();
}

RunConfig load_run_config(const std::string& path, const std::vector<std::string>& overrides) {
  ConfigReader r = ConfigReader::from_file(path);
  for (const auto& o : overrides) r.apply_override(o);

  RunConfig c;
  c.origin = path;

  // [scene]
  c.scene.path = kScenePath.read(r);
  if (c.scene.path.empty())
    r.fail(KeyError("scene.path", "the scene path is empty (need a .gltf or .glb file, or "
                                  "builtin:NAME)"));
  c.scene.resolved = resolve_scene_path(c.scene.path, r.base_dir());
  c.scene.camera = kSceneCamera.read(r);
  for (const char* key :
       {"scene.path", "scene.camera", "layout.kind", "camera.eye", "camera.target", "camera.up",
        "camera.vfov", "functional.rays_in_flight", "functional.timed", "sample.rate",
        "sample.target_ci", "chip.units", "l2.enable"})
    c.origins[key] = r.where(key);

  // [camera]: an explicit pinhole camera (all of eye, target; up and vfov default), or
  // camera.vfov alone: the field of view of the scene's camera.
  const auto eye = kEye.read(r), target = kTarget.read(r);
  const bool any_camera = eye || target || r.has(kUp.key());
  if (!any_camera && r.has(kVfov.key())) c.scene_vfov_deg = static_cast<float>(kVfov.read(r));
  if (any_camera) {
    // up and vfov are read (and their defaults recorded) only for a camera of the config.
    const glm::vec3 up = *kUp.read(r);
    const double vfov = kVfov.read(r);
    if (!eye || !target)
      r.fail(KeyError({"camera.eye", "camera.target", "camera.up", "camera.vfov"},
                      "camera.eye and camera.target are both required for a camera of the "
                      "config (camera.up or camera.vfov with them; camera.vfov alone sets the "
                      "scene camera's)"));
    if (!c.scene.camera.empty())
      r.fail(KeyError({"scene.camera", "camera.eye", "camera.target", "camera.up", "camera.vfov"},
                      "give scene.camera or camera.*, not both"));
    c.camera = CameraDesc{"config", *eye, *target, up, static_cast<float>(vfov)};
  }

  // [image]
  c.image.width = static_cast<int>(kWidth.read(r));
  c.image.height = static_cast<int>(kHeight.read(r));
  c.image.write_png = kPng.read(r);
  c.image.heatmaps = kHeatmaps.read(r);

  // Each part's subtree, read and checked by the part that declares it.
  c.tracer = read_tracer_params(r);
  c.kdtree = read_kd_build_params(r);
  c.layout.kinds = read_layout_kinds(r);
  c.l1 = read_node_l1_config(r);
  c.dcache = read_dcache_config(r);
  c.chip = read_chip_params(r);

  // [sim], [report]: the tier; the cycle tier's keys are read whatever the tier, so they are
  // validated and in the effective config.
  c.sim.tier = read_tier_name(r);
  c.report.frames_per_second = kFramesPerSecond.read(r);
  c.sim.clock_mhz = read_clock_mhz(r);
  c.unit = read_unit_params(r);
  c.sim.vcd_path = read_vcd_path(r);
  // A timed tier with one layout writes the file itself (several: files beside it, named
  // from its stem; the functional tier none): each checked before anything runs.
  if (c.sim.tier != "functional" && !c.sim.vcd_path.empty())
    for (const std::string& kind : c.layout.kinds) {
      const std::string vcd_file = c.layout.kinds.size() == 1
                                       ? c.sim.vcd_path
                                       : layout_vcd_path(c.sim.vcd_path, kind);
      std::error_code vcd_ec;
      if (std::filesystem::is_directory(vcd_file, vcd_ec))
        r.fail(KeyError("sim.vcd", vcd_file + ": is a directory (need a file name)"));
    }
  c.dram = read_dram_params(r);
  // The timed tiers place a request (a line, or a burst straight to DRAM) in a bank and a row
  // by its first byte: it must fit in a row (the functional tier has no rows).
  if (c.sim.tier != "functional") {
    const uint64_t request = std::max<uint64_t>(
        {c.l1.params.cache.line_bytes, c.dcache.enable ? c.dcache.params.cache.line_bytes : 0,
         c.dram.burst_bytes()});
    if (c.dram.row_bytes < request)
      r.fail(KeyError("dram.row_bytes", std::to_string(c.dram.row_bytes) +
                                            " is smaller than a request to DRAM (" +
                                            std::to_string(request) +
                                            " bytes: l1.line, dcache.line or the burst)"));
  }
  c.functional = read_functional_params(r);
  if (c.sim.tier == "rtl") {
    // The rtl tier is the cycle tier with the Verilated node L1.
    if (r.has("l1.model") && c.l1.model != "rtl")
      r.fail(KeyError({"l1.model", "sim.tier"}, "sim.tier = \"rtl\" uses the RTL L1, not \"" +
                                                    c.l1.model + "\""));
    c.l1.model = "rtl";
  }
  if (c.l1.model == "rtl" && c.sim.tier == "functional")
    r.fail(KeyError({"l1.model", "sim.tier"}, "\"rtl\" needs sim.tier = \"cycle\" or \"rtl\""));
  // The checks across subtrees, once.
  try {
    validate(c.cycle());
  } catch (const KeyError& e) {
    r.fail(e);
  }

  c.sample = read_sample_params(r, c.tracer.order);
  // The chip (several units, or an L2) is modelled by the plain functional tier so far.
  if (!c.chip.single_unit()) {
    const std::string chip_key = c.chip.units > 1 ? "chip.units" : "l2.enable";
    const auto refuse = [&](const std::string& key, const std::string& what) {
      r.fail(KeyError({chip_key, key}, "a chip of several units or with an L2 runs in the "
                                       "plain functional tier only so far, not " + what));
    };
    if (c.sim.tier != "functional") refuse("sim.tier", "sim.tier = \"" + c.sim.tier + "\"");
    if (c.functional.rays_in_flight > 1)
      refuse("functional.rays_in_flight", "with functional.rays_in_flight > 1");
    if (c.functional.timed) refuse("functional.timed", "in the timed mode");
    if (c.sample.rate < 1.0) refuse("sample.rate", "sampled");
    if (c.sample.target_ci > 0.0) refuse("sample.target_ci", "sampled");
  }
  r.reject_unknown_keys();
  c.effective = r.effective();
  return c;
}

}  // namespace rtusim
