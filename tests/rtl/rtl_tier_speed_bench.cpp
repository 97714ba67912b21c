// Speed of the rtl tier against the cycle tier in the same run (not a test): primary rays of a
// scene through CycleBackend with l1.model = cpp and = rtl, one batch per 4096 rays; node
// fetches per second, medians of REPS runs each, and whether counters and cycles are equal.
// Usage: rtl_tier_speed_bench [SCENE.gltf|builtin:cornell] [WIDTH] [REPS]
// (default: $RTUSIM_SCENES/kitchen/kitchen.gltf if present, else builtin:cornell; 128; 3);
// rays in flight 1, 32 and 128.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_timing.h"
#include "kdtree/sah_builder.h"
#include "layout/dfl_layout.h"
#include "mem/node_l1.h"
#include "model/cycle_backend.h"
#include "scene/builtin_scene.h"
#include "scene/gltf_loader.h"
#include "scene/pinhole_camera.h"
#include "util/stats.h"

using namespace rtusim;

namespace {

struct Run {
  Stats stats;
  uint64_t cycles = 0;
};

Run trace_all(const MemoryImage& image, const std::vector<RayRecord>& rays, uint32_t rif,
              const char* model) {
  CycleParams p;
  p.unit.rays_in_flight = rif;
  p.node_l1_model = model;
  std::vector<Hit> hits(rays.size());
  CycleBackend backend(image, p);
  const size_t batch = 4096;
  for (size_t i = 0; i < rays.size(); i += batch) {
    const size_t n = std::min(batch, rays.size() - i);
    backend.trace(std::span<const RayRecord>(rays).subspan(i, n),
                  std::span<Hit>(hits).subspan(i, n));
  }
  Run r;
  backend.write_stats(r.stats);
  r.cycles = backend.cycles();
  return r;
}

bool same(const Run& a, const Run& b) {
  for (const char* key : {"l1.hits", "l1.misses", "l1.primary_misses", "l1.merged_misses",
                          "l1.mshr_stall_cycles", "l1.mean_miss_latency_cycles",
                          "dram.bytes.nodes"})
    if (a.stats.at(key) != b.stats.at(key)) return false;
  return a.cycles == b.cycles;
}

}  // namespace

int main(int argc, char** argv) {
  const char* env = std::getenv("RTUSIM_SCENES");
  std::string scene_path = std::string(env ? env : RTUSIM_SCENES_DEFAULT) + "/kitchen/kitchen.gltf";
  if (argc > 1) scene_path = argv[1];
  else if (!std::filesystem::exists(scene_path)) scene_path = "builtin:cornell";
  const int w = argc > 2 ? std::atoi(argv[2]) : 128;
  const int reps = argc > 3 ? std::max(1, std::atoi(argv[3])) : 3;
  const Scene scene = scene_path.starts_with("builtin:")
                          ? make_builtin_scene(scene_path.substr(8))
                          : load_gltf(scene_path);
  const KdTree tree = build_sah_kd_tree(scene, KdBuildParams{});
  const MemoryImage image = DflLayout().build_image(tree, scene);
  const CameraDesc desc = scene.cameras.empty() ? CameraDesc{} : scene.cameras.front();
  const PinholeCamera cam(desc, w, w);
  std::vector<RayRecord> rays;
  for (int y = 0; y < w; ++y)
    for (int x = 0; x < w; ++x) {
      RayRecord r;
      r.ray = cam.generate(x, y);
      r.pixel = static_cast<uint32_t>(y * w + x);
      rays.push_back(r);
    }
  std::printf("%s, %dx%d primary rays, dfl, 8192/4/64 lru; medians of %d runs\n",
              scene_path.c_str(), w, w, reps);
  std::printf("%8s %12s %10s %14s %14s %9s %s\n", "in_flight", "fetches", "cycles",
              "cpp_fetch/s", "rtl_fetch/s", "slowdown", "counters+cycles");
  for (const uint32_t rif : {1u, 32u, 128u}) {
    Run cpp, rtl;
    const double cpp_s =
        bench_timing::median_seconds(reps, [&] { cpp = trace_all(image, rays, rif, "cpp"); });
    const double rtl_s =
        bench_timing::median_seconds(reps, [&] { rtl = trace_all(image, rays, rif, "rtl"); });
    const double fetches = rtl.stats.at("l1.accesses").get<double>();
    std::printf("%8u %12.0f %10llu %14.3g %14.3g %8.1fx %s\n", rif, fetches,
                static_cast<unsigned long long>(rtl.cycles), fetches / cpp_s, fetches / rtl_s,
                rtl_s / cpp_s, same(cpp, rtl) ? "equal" : "DIFFER");
  }
}
