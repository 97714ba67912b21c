// Build benchmark of the SAH kd-tree builder: synthetic scenes (a grid of tessellated spheres of
// ~1M triangles, random soups), or the glTF files given on the command line. Peak RSS is read
// after each build: run one scene per process to see one scene's peak.
#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "kdtree/sah_builder.h"
#include "scene/gltf_loader.h"
#include "scene/scene.h"

namespace {

using rtusim::Scene;

// A `side`^3 grid of UV spheres with `stacks` x `slices` quads each (two triangles per quad).
Scene spheres_grid(int side, int stacks, int slices) {
  Scene scene;
  scene.source = "builtin:spheres_grid";
  for (int gx = 0; gx < side; ++gx)
    for (int gy = 0; gy < side; ++gy)
      for (int gz = 0; gz < side; ++gz) {
        const glm::vec3 center(3.0f * gx, 3.0f * gy, 3.0f * gz);
        const uint32_t base = static_cast<uint32_t>(scene.positions.size());
        for (int i = 0; i <= stacks; ++i) {
          const double theta = std::numbers::pi * i / stacks;
          for (int j = 0; j <= slices; ++j) {
            const double phi = 2.0 * std::numbers::pi * j / slices;
            scene.positions.push_back(center + glm::vec3(std::sin(theta) * std::cos(phi),
                                                         std::cos(theta),
                                                         std::sin(theta) * std::sin(phi)));
          }
        }
        for (int i = 0; i < stacks; ++i)
          for (int j = 0; j < slices; ++j) {
            const uint32_t a = base + i * (slices + 1) + j, b = a + slices + 1;
            scene.triangles.push_back({a, b, a + 1});
            scene.triangles.push_back({a + 1, b, b + 1});
          }
      }
  scene.triangle_material.assign(scene.triangles.size(), 0);
  return scene;
}

// `count` random triangles of size ~`size` in the unit cube scaled by 100.
Scene random_soup(uint32_t count, float size, uint32_t seed) {
  Scene scene;
  scene.source = "builtin:random_soup";
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (uint32_t t = 0; t < count; ++t) {
    const glm::vec3 c(u(rng) * 100.0f, u(rng) * 100.0f, u(rng) * 100.0f);
    const uint32_t base = static_cast<uint32_t>(scene.positions.size());
    for (int k = 0; k < 3; ++k)
      scene.positions.push_back(c + (glm::vec3(u(rng), u(rng), u(rng)) - 0.5f) * size);
    scene.triangles.push_back({base, base + 1, base + 2});
  }
  scene.triangle_material.assign(scene.triangles.size(), 0);
  return scene;
}

void bench(const std::string& name, const Scene& scene) {
  const rtusim::KdBuildParams params;
  const rtusim::KdTree tree = rtusim::build_sah_kd_tree(scene, params);
  const rtusim::KdTreeReport& r = tree.report;
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf(
      "%-22s tris %9u  build_s %7.3f  nodes %9llu  leaves %9llu  empty %8llu  max_depth %2u  "
      "mean_leaf_depth %5.2f  refs/tri %5.2f  sah %8.2f  peak_build_bytes %11llu  "
      "process_max_rss_bytes %11llu\n",
      name.c_str(), scene.triangle_count(), r.build_seconds, (unsigned long long)r.nodes,
      (unsigned long long)r.leaves, (unsigned long long)r.empty_leaves, r.max_depth,
      r.mean_leaf_depth, r.refs_per_triangle, r.sah_cost, (unsigned long long)r.peak_build_bytes,
      (unsigned long long)usage.ru_maxrss * 1024ull);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  // With arguments: only the given glTF files. Without: the synthetic set.
  if (argc > 1) {
    for (int i = 1; i < argc; ++i) {
      bench(argv[i], rtusim::load_gltf(argv[i]));
    }
    return 0;
  }
  bench("random_soup_100k", random_soup(100000, 1.5f, 1));
  bench("spheres_grid_1m", spheres_grid(4, 90, 90));  // 64 spheres x 16200 triangles
  bench("random_soup_1m", random_soup(1000000, 0.7f, 2));
  return 0;
}
