// Speed of the rtl tier against the cycle tier on the same run (not a test): primary rays of a
// scene through CycleBackend with l1.model = cpp and = rtl, one batch per image row block.
// Usage: rtl_tier_speed_bench [SCENE.gltf|builtin:cornell] [WIDTH] [RAYS_IN_FLIGHT]
// (default: $RTUSIM_SCENES/kitchen/kitchen.gltf if present, else builtin:cornell; 128; 32).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "kdtree/sah_builder.h"
#include "layout/dfl_layout.h"
#include "mem/node_l1.h"
#include "model/cycle_backend.h"
#include "scene/builtin_scene.h"
#include "scene/gltf_loader.h"
#include "scene/pinhole_camera.h"
#include "util/stats.h"

using namespace rtusim;

int main(int argc, char** argv) {
  const char* env = std::getenv("RTUSIM_SCENES");
  std::string scene_path = std::string(env ? env : RTUSIM_SCENES_DEFAULT) + "/kitchen/kitchen.gltf";
  if (argc > 1) scene_path = argv[1];
  else if (!std::filesystem::exists(scene_path)) scene_path = "builtin:cornell";
  const int w = argc > 2 ? std::atoi(argv[2]) : 128;
  const uint32_t rif = argc > 3 ? static_cast<uint32_t>(std::atoi(argv[3])) : 32;
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
  std::printf("%s, %dx%d primary rays, dfl, rays_in_flight %u\n", scene_path.c_str(), w, w, rif);
  double cpp_seconds = 0;
  for (const char* model : {"cpp", "rtl"}) {
    CycleParams p;
    p.unit.rays_in_flight = rif;
    p.node_l1_model = model;
    std::vector<Hit> hits(rays.size());
    const auto t0 = std::chrono::steady_clock::now();
    CycleBackend backend(image, p);
    const size_t batch = 4096;
    for (size_t i = 0; i < rays.size(); i += batch) {
      const size_t n = std::min(batch, rays.size() - i);
      backend.trace(std::span<const RayRecord>(rays).subspan(i, n),
                    std::span<Hit>(hits).subspan(i, n));
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    Stats st;
    backend.write_stats(st);
    const auto fetches = st.at("l1.accesses").get<uint64_t>();
    if (std::string(model) == "cpp") cpp_seconds = s;
    std::printf("  l1.model %s: %.3f s, %llu cycles, %llu node fetches (%.0f fetches/s), "
                "l1.misses %llu, dram.bytes.nodes %llu%s\n",
                model, s, static_cast<unsigned long long>(backend.cycles()),
                static_cast<unsigned long long>(fetches), double(fetches) / s,
                static_cast<unsigned long long>(st.at("l1.misses").get<uint64_t>()),
                static_cast<unsigned long long>(st.at("dram.bytes.nodes").get<uint64_t>()),
                std::string(model) == "rtl"
                    ? (", slowdown " + std::to_string(s / cpp_seconds) + "x").c_str()
                    : "");
  }
}
