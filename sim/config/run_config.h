// The validated parameters of one run: TOML file + overrides -> RunConfig, in one place.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "config/config_reader.h"

#include "cache/stream_caches.h"
#include "kdtree/kd_tree.h"
#include "model/cycle_params.h"
#include "sample/sample_params.h"
#include "scene/scene.h"
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

// Which fidelity tier runs the traversal.
enum class Tier {
  kFunctional,  // host traversal through the behavioural caches (no time)
  kCycle,       // the SystemC traversal unit, L1 with MSHRs and DRAM timing
  kRtl,         // the cycle tier with the Verilated RTL node L1
};

struct SimParams {
  Tier tier = Tier::kFunctional;
  std::string tier_name = "functional";
  double frames_per_second = 30.0;  // report.frames_per_second: for GB/s figures
};

struct RunConfig {
  std::string origin;  // the config file
  SceneParams scene;
  std::optional<CameraDesc> camera;  // camera.eye/target/up/vfov, when given
  ImageParams image;
  TracerParams tracer;
  KdBuildParams kdtree;
  std::vector<std::string> layouts;  // layout.kind, one or more
  FetchCacheParams caches;           // l1.*, dcache.*
  SimParams sim;
  CycleParams cycle;                 // sim.*, isect.*, l1.*, dcache.*, dram.* of the cycle tier
  SampleParams sample;               // sample.*: sampled simulation
  int functional_rays_in_flight = 1;  // functional.rays_in_flight: the interleaved mode
  toml::table effective;             // every key with the value used
};

// Reads and validates `path` with `overrides` (KEY=VALUE). Throws InputError on bad input.
RunConfig load_run_config(const std::string& path, const std::vector<std::string>& overrides);

// Resolves a scene path: "builtin:NAME" stays; a leading $RTUSIM_SCENES (or ${RTUSIM_SCENES})
// becomes the environment variable, or ../shared/scenes beside the project; other relative
// paths are relative to `base_dir`.
std::string resolve_scene_path(const std::string& path, const std::string& base_dir);

// The scenes directory: $RTUSIM_SCENES, or ../shared/scenes beside the project.
std::string scenes_dir();

}  // namespace rtusim
