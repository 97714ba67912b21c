// Build benchmark of the SAH kd-tree builder: synthetic scenes (a grid of tessellated spheres of
// ~1M triangles, random soups), plus any glTF files given on the command line (read here with a
// throwaway tinygltf reader: positions and indices of every primitive, no transforms, since the
// shared scenes are flattened to world space).
#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "kdtree/sah_builder.h"
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

// Throwaway glTF reader: every triangle primitive's positions and indices.
bool load_gltf(const std::string& path, Scene& scene) {
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  if (!loader.LoadASCIIFromFile(&model, &err, &warn, path)) {
    std::fprintf(stderr, "%s: %s\n", path.c_str(), err.c_str());
    return false;
  }
  scene.source = path;
  for (const tinygltf::Mesh& mesh : model.meshes)
    for (const tinygltf::Primitive& prim : mesh.primitives) {
      if (prim.mode != TINYGLTF_MODE_TRIANGLES || prim.indices < 0) continue;
      const auto pos_it = prim.attributes.find("POSITION");
      if (pos_it == prim.attributes.end()) continue;
      const tinygltf::Accessor& pa = model.accessors[pos_it->second];
      const tinygltf::BufferView& pv = model.bufferViews[pa.bufferView];
      const uint8_t* pdata = model.buffers[pv.buffer].data.data() + pv.byteOffset + pa.byteOffset;
      const size_t pstride = pv.byteStride ? pv.byteStride : 12;
      const uint32_t base = static_cast<uint32_t>(scene.positions.size());
      for (size_t i = 0; i < pa.count; ++i) {
        glm::vec3 p;
        std::memcpy(&p, pdata + i * pstride, sizeof p);
        scene.positions.push_back(p);
      }
      const tinygltf::Accessor& ia = model.accessors[prim.indices];
      const tinygltf::BufferView& iv = model.bufferViews[ia.bufferView];
      const uint8_t* idata = model.buffers[iv.buffer].data.data() + iv.byteOffset + ia.byteOffset;
      auto index = [&](size_t i) -> uint32_t {
        switch (ia.componentType) {
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return idata[i];
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            uint16_t v;
            std::memcpy(&v, idata + 2 * i, 2);
            return v;
          }
          default: {
            uint32_t v;
            std::memcpy(&v, idata + 4 * i, 4);
            return v;
          }
        }
      };
      for (size_t i = 0; i + 2 < ia.count; i += 3)
        scene.triangles.push_back({base + index(i), base + index(i + 1), base + index(i + 2)});
    }
  scene.triangle_material.assign(scene.triangles.size(), 0);
  return true;
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
      Scene scene;
      if (!load_gltf(argv[i], scene)) return 1;
      bench(argv[i], scene);
    }
    return 0;
  }
  bench("random_soup_100k", random_soup(100000, 1.5f, 1));
  bench("spheres_grid_1m", spheres_grid(4, 90, 90));  // 64 spheres x 16200 triangles
  bench("random_soup_1m", random_soup(1000000, 0.7f, 2));
  return 0;
}
