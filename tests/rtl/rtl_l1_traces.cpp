#include "rtl_l1_traces.h"

#include <algorithm>
#include <filesystem>
#include <memory>
#include <random>
#include <string>

#include "app/run_config.h"
#include "kdtree/sah_builder.h"
#include "layout/dfl_layout.h"
#include "scene/builtin_scene.h"
#include "scene/gltf_loader.h"
#include "scene/pinhole_camera.h"
#include "traversal/traversal.h"

namespace rtusim::rtltest {

namespace {

struct NodeRecorder {
  std::vector<uint64_t>* out;
  void fetch(Stream s, uint64_t addr, uint32_t /*bytes*/) {
    if (s == Stream::kNode) out->push_back(addr);
  }
};

std::vector<uint64_t> node_trace(const Scene& scene, const std::string& camera, int w, int h) {
  const KdTree tree = build_sah_kd_tree(scene, KdBuildParams{});
  const MemoryImage image = DflLayout().build_image(tree, scene);
  CameraDesc desc = scene.cameras.empty() ? CameraDesc{} : scene.cameras.front();
  for (const CameraDesc& c : scene.cameras)
    if (c.name == camera) desc = c;
  const PinholeCamera cam(desc, w, h);
  std::vector<uint64_t> trace;
  NodeRecorder sink{&trace};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) traverse<DflLayout>(image, cam.generate(x, y), false, sink);
  return trace;
}

}  // namespace

std::vector<uint64_t> clustered_trace(uint32_t seed, size_t count, uint32_t line_bytes) {
  std::mt19937_64 rng(seed);
  std::vector<uint64_t> bases(16);
  for (uint64_t& b : bases) b = rng() % (1u << 20);
  std::vector<uint64_t> trace;
  trace.reserve(count);
  uint64_t base = bases[0];
  while (trace.size() < count) {
    const uint64_t r = rng() % 100;
    if (r < 10) {
      base = rng() % (1u << 20);          // a new cluster
      bases[rng() % bases.size()] = base;
    } else if (r < 40) {
      base = bases[rng() % bases.size()];  // back to a recent one
    }
    const size_t run = 1 + rng() % 24;
    for (size_t i = 0; i < run && trace.size() < count; ++i)
      trace.push_back((base + (rng() % (8 * line_bytes))) & ~uint64_t{7});
  }
  return trace;
}

std::vector<uint64_t> set_thrash_trace(uint32_t seed, size_t count, uint64_t size_bytes,
                                       uint32_t assoc, uint32_t line_bytes) {
  std::mt19937_64 rng(seed);
  const uint64_t way_bytes = size_bytes / assoc;  // lines this far apart share a set
  std::vector<uint64_t> lines;
  for (uint64_t set : {uint64_t{1}, uint64_t{2}})
    for (uint32_t k = 0; k < assoc + 2; ++k) lines.push_back(k * way_bytes + set * line_bytes);
  std::vector<uint64_t> trace(count);
  // Skewed choice: recency matters, so LRU and tree-PLRU evict differently.
  std::geometric_distribution<uint32_t> pick(0.35);
  for (uint64_t& a : trace) {
    const uint32_t i = std::min<uint32_t>(pick(rng), static_cast<uint32_t>(lines.size()) - 1);
    std::rotate(lines.begin(), lines.begin() + i, lines.begin() + i + 1);  // to the front
    a = lines[0] + (rng() % line_bytes & ~uint64_t{3});
  }
  return trace;
}

const std::vector<uint64_t>& cornell_node_trace() {
  static const std::vector<uint64_t> trace =
      node_trace(make_builtin_scene("cornell"), "default", 128, 128);
  return trace;
}

const std::vector<uint64_t>* kitchen_node_trace() {
  static const std::unique_ptr<std::vector<uint64_t>> trace = [] {
    const std::string path = scenes_dir() + "/kitchen/kitchen.gltf";
    if (!std::filesystem::exists(path)) return std::unique_ptr<std::vector<uint64_t>>();
    return std::make_unique<std::vector<uint64_t>>(
        node_trace(load_gltf(path), "bart_camera_t0", 128, 128));
  }();
  return trace.get();
}

}  // namespace rtusim::rtltest
