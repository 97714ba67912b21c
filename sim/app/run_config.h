// The validated, immutable parameters of one run, one struct per config subtree:
// TOML file + `--set` overrides -> declared keys (config/param.h) -> RunConfig, read and
// validated once. The tiers' params are derived from it (fetch_caches(), cycle()).
#pragma once
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "cache/fetch_cache.h"
#include "chip/chip_params.h"
#include "kdtree/kd_tree.h"
#include "mem/dram/dram_params.h"
#include "mem/l1_params.h"
#include "model/cycle_params.h"
#include "model/unit_params.h"
#include "sample/sample_params.h"
#include "scene/scene.h"
#include "tier/functional_params.h"
#include "tracer/tracer_params.h"

namespace rtusim {

struct SceneParams {
  std::string path;    // as written in the config
  std::string resolved;  // file path after $RTUSIM_SCENES / relative resolution, or builtin:NAME
  std::string camera;  // glTF camera node name ("" = explicit camera.* or the first camera)
};

struct ImageParams {
  int width = 256;
  int height = 256;
  bool write_png = true;  // image.png: write the rendered frame
  bool heatmaps = true;   // image.heatmaps: per-layout DRAM-traffic heatmaps (and ODFL-DFL)
};

struct LayoutParams {
  std::vector<std::string> kinds;  // layout.kind, one or more
};

// The sim.* keys of the run itself (defaults: their declarations in tier.cpp, cycle_params.cpp).
struct SimParams {
  std::string tier;        // sim.tier: one of tier_names()
  double clock_mhz = 0.0;  // sim.clock_mhz
  std::string vcd_path;    // sim.vcd
};

struct ReportParams {
  double frames_per_second = 30.0;  // report.frames_per_second: for GB/s figures
};

struct RunConfig {
  std::string origin;  // the config file
  // Where the values that later checks name came from (ConfigReader::where): "scene.path",
  // "scene.camera", "layout.kind", each camera.* key, and the keys trace refuses
  // (functional.rays_in_flight, functional.timed, sample.rate, sample.target_ci, chip.units, l2.enable).
  std::map<std::string, std::string> origins;
  SceneParams scene;
  std::optional<CameraDesc> camera;  // camera.eye/target/up/vfov, when given
  std::optional<float> scene_vfov_deg;  // camera.vfov alone: the scene camera's field of view
  ImageParams image;
  TracerParams tracer;
  KdBuildParams kdtree;
  LayoutParams layout;
  L1Config l1;      // l1.*: the node L1 (model rtl with sim.tier = rtl)
  L1Config dcache;  // dcache.*: lists and triangles (enable = false: straight to DRAM)
  ChipParams chip;  // chip.*, l2.*: the units (each with l1 and dcache) and the shared L2
  UnitParams unit;  // sim.rays_in_flight/step_cycles/stack_depth, isect.*
  DramParams dram;  // dram.*
  SimParams sim;
  ReportParams report;
  FunctionalParams functional;  // functional.*: the functional tier's interleaved mode
  SampleParams sample;          // sample.*: sampled simulation
  toml::table effective;  // every key with the value used

  // The functional tier's caches (each unit's, on a chip).
  FetchCacheParams fetch_caches() const;
  // The cycle tier's params (derived; validated when the config was read).
  CycleParams cycle() const;
};

// Reads and validates `path` with `overrides` (KEY=VALUE). Throws InputError on bad input.
RunConfig load_run_config(const std::string& path, const std::vector<std::string>& overrides);

// The VCD file of `layout` in a run of several layouts: sim.vcd's stem + "_" + layout, beside it.
std::string layout_vcd_path(const std::string& vcd_path, const std::string& layout);

// Resolves a scene path: "builtin:NAME" stays; a leading $RTUSIM_SCENES (or ${RTUSIM_SCENES})
// becomes the environment variable, or ../shared/scenes beside the project; other relative
// paths are relative to `base_dir`.
std::string resolve_scene_path(const std::string& path, const std::string& base_dir);

// The scenes directory: $RTUSIM_SCENES, or ../shared/scenes beside the project.
std::string scenes_dir();

}  // namespace rtusim
