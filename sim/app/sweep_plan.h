// A sweep spec: a run config plus a [sweep] table, expanded into points and jobs.
//
//   [sweep]
//   l1.size = [1024, 2048, 4096]        # a key and its values: one dimension of the product
//   l1.assoc = [1, 2, 4, "full"]        # "full" = one set (l1.assoc = l1.size / l1.line)
//   [[sweep.group.scene]]               # a named group: keys that vary together, one entry each
//   scene.path = "$RTUSIM_SCENES/kitchen/kitchen.gltf"
//   scene.camera = "bart_camera_t0"
//
// The points are the product of the dimensions; a point is the base config (the spec without
// [sweep], then the command's --set) with the point's overrides, exactly what `rtusim run BASE
// --set …` runs. Plain functional points that differ only in cache keys and layout.kind form one
// job (one prepared scene and tree, one traced frame per layout for all their caches); every
// other point (a timed tier, sampled, the functional tier's interleaved or timed mode) is its
// own job. Before anything runs every point is validated by load_run_config, and each distinct
// scene and camera is loaded and checked; errors name the spec file, the key and the value.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "cache/fetch_cache.h"
#include "chip/chip_params.h"

namespace rtusim {

struct SweepPoint {
  std::vector<std::string> overrides;  // KEY=VALUE (TOML), after the --set of the sweep
  std::vector<std::string> cells;      // CSV text of each swept column, as in the spec (a
                                       // relative scene.path made absolute)
  FetchCacheParams caches;             // the node L1 and data cache of the point
  ChipParams chip;                     // its units and L2
  std::string layout;                  // its one layout.kind
  // Run alone by simulate(), as `rtusim run` runs it: a timed tier (cycle, rtl), a sampled run,
  // or the functional tier's interleaved or timed mode. The one-pass evaluation of a job's
  // caches traces the whole frame one ray at a time, the plain functional tier only.
  bool alone = false;
  size_t job = 0;
};

struct SweepJob {
  std::vector<size_t> points;  // in point order
  bool alone = false;          // one point, run by simulate()
  // Chip points (several units or an L2) that differ only in their LRU L2's l2.size and
  // l2.assoc (and layout.kind): one traced frame per layout through the units' caches, every L2
  // evaluated in one pass over the requests it takes (L2LruSweep).
  bool l2_family = false;
};

struct SweepPlan {
  std::string spec_path;
  std::string spec_text;
  std::vector<std::string> sets;     // the command's --set KEY=VALUE
  std::string base_toml;             // the spec without [sweep], the --set applied; scene path absolute
  std::vector<std::string> columns;  // the swept keys, in dimension order
  std::vector<SweepPoint> points;    // product order: the last dimension varies fastest
  std::vector<SweepJob> jobs;        // in order of their first point
};

// Reads, expands and validates the spec: every point's config and, with `check_scenes`, every
// scene it loads and camera it asks for (the runners' jobs plan again without). Throws
// InputError naming the spec, key and value.
SweepPlan plan_sweep(const std::string& spec_path, const std::vector<std::string>& sets,
                     bool check_scenes = true);

// The message of bad input that job `job` met when it ran (`what`, about its base config
// `base_path` or the --set that applied a point's key), naming the spec and the keys the job's
// points share instead.
std::string job_error(const SweepPlan& plan, size_t job, const std::string& base_path,
                      const std::string& what);


}  // namespace rtusim
