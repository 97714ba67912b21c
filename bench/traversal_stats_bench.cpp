// Per-ray work of the host kd-tree traversal on the primary rays traversal_bench times (DFL image,
// 512x512): interior steps, leaves, empty leaves, triangle tests, repeated tests of one triangle
// (shared by several leaves on the ray), stack pushes and pops. No timing.
// Usage: traversal_stats_bench [--trace REPS] [SCENE ...] (names under $RTUSIM_SCENES; default
// sponza and kitchen). --trace only traces every ray REPS times through traverse() with no sink,
// in one out-of-line function (trace_all) for a profiler: perf record, or callgrind with
// --toggle-collect='*trace_all*' on a build without AVX-512 (valgrind has none).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unordered_set>
#include <vector>

#include "app/run_config.h"
#include "kdtree/sah_builder.h"
#include "layout/dfl_layout.h"
#include "scene/gltf_loader.h"
#include "scene/pinhole_camera.h"
#include "traversal/traversal.h"

using namespace rtusim;

namespace {

// Keeps the triangle fetch addresses of a ray.
struct TriangleSink {
  std::vector<uint64_t> tri_addrs;
  void fetch(Stream s, uint64_t addr, uint32_t) {
    if (s == Stream::kTriangle) tri_addrs.push_back(addr);
  }
};

// Every ray traced once with no sink (the code traversal_bench times).
[[gnu::noinline]] double trace_all(const MemoryImage& image, const std::vector<Ray>& rays) {
  NullFetchSink sink;
  double checksum = 0.0;
  for (const Ray& ray : rays) checksum += traverse<DflLayout>(image, ray, false, sink).triangle;
  return checksum;
}

}  // namespace

int main(int argc, char** argv) {
  int trace_reps = 0;  // > 0: --trace
  std::vector<std::string> scenes;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--trace" && i + 1 < argc)
      trace_reps = std::max(1, std::atoi(argv[++i]));
    else
      scenes.push_back(argv[i]);
  }
  if (scenes.empty()) scenes = {"sponza_dabrovic", "kitchen"};
  const int w = 512, h = 512;
  for (const std::string& name : scenes) {
    const Scene scene = load_gltf(scenes_dir() + "/" + name + "/" + name + ".gltf");
    const KdTree tree = build_sah_kd_tree(scene, KdBuildParams{});
    const MemoryImage image = DflLayout().build_image(tree, scene);
    const PinholeCamera cam(scene.cameras.front(), w, h);
    if (trace_reps > 0) {
      std::vector<Ray> all;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) all.push_back(cam.generate(x, y));
      double checksum = 0.0;
      for (int r = 0; r < trace_reps; ++r) checksum += trace_all(image, all);
      std::printf("%s checksum %g\n", name.c_str(), checksum);
      continue;
    }
    uint64_t rays = 0, hits = 0, interior = 0, leaves = 0, empty = 0, tests = 0, repeats = 0,
             pushes = 0, pops = 0, culled = 0, chunked_leaves = 0, chunked_tests = 0,
             leaves_after_hit = 0, scalar_tests = 0, scalar_repeats = 0, ring_hits = 0, tests_after_hit = 0, max_sp = 0, begin_done = 0;
    uint64_t leaf_hist[8] = {};
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const Ray ray = cam.generate(x, y);
        TraversalState s;
        traversal_begin(s, image, ray, false);
        if (s.done) ++begin_done;
        TriangleSink sink;
        std::unordered_set<uint64_t> seen;
        uint64_t ring[8] = {~0ull, ~0ull, ~0ull, ~0ull, ~0ull, ~0ull, ~0ull, ~0ull};
        unsigned ring_pos = 0;
        for (;;) {
          const int sp0 = s.sp;
          const float t0 = s.hit.t;
          const size_t f0 = sink.tri_addrs.size();
          const StepKind k = traversal_step<DflLayout>(s, image, sink);
          if (k == StepKind::kDone) break;
          if (k == StepKind::kInterior) {
            ++interior;
            pushes += s.sp > sp0;
            max_sp = std::max<uint64_t>(max_sp, s.sp);
          } else {
            ++leaves;
            const uint32_t n = s.leaf_prims_tested;
            empty += n == 0;
            ++leaf_hist[std::min<uint32_t>(n, 7)];
            tests += n;
            if (n >= 4) {
              ++chunked_leaves;
              chunked_tests += n;
            }
            if (t0 < 1e30f) {
              ++leaves_after_hit;
              tests_after_hit += n;
            }
            for (size_t i = f0; i < sink.tri_addrs.size(); ++i) {
              const bool rep = !seen.insert(sink.tri_addrs[i]).second;
              repeats += rep;
              if (n < 4) {
                scalar_tests += 1;
                scalar_repeats += rep;
                bool in_ring = false;
                for (uint64_t a : ring) in_ring |= a == sink.tri_addrs[i];
                ring_hits += in_ring;
                if (!in_ring) ring[ring_pos++ & 7] = sink.tri_addrs[i];
              }
            }
            if (!s.done) {  // popped the next node, after `culled` entries beyond the hit
              ++pops;
              culled += sp0 - s.sp - 1;
            }
          }
        }
        ++rays;
        hits += s.hit.valid();
      }
    const double r = double(rays);
    std::printf("%s: %u tris, %llu nodes, rays %llu, hit %.3f, missing bounds %.3f\n",
                name.c_str(), scene.triangle_count(), (unsigned long long)tree.report.nodes,
                (unsigned long long)rays, hits / r, begin_done / r);
    std::printf("  per ray: interior %.2f leaves %.2f (empty %.2f) tests %.2f (repeats %.2f) "
                "pushes %.2f pops %.2f culled-pops %.2f max_sp %llu\n",
                interior / r, leaves / r, empty / r, tests / r, repeats / r, pushes / r, pops / r,
                culled / r, (unsigned long long)max_sp);
    std::printf("  chunked leaves %.2f (tests %.2f); after first hit: leaves %.2f tests %.2f\n",
                chunked_leaves / r, chunked_tests / r, leaves_after_hit / r, tests_after_hit / r);
    std::printf("  scalar-leaf tests %.2f, repeats %.2f, caught by an 8-entry ring %.2f\n",
                scalar_tests / r, scalar_repeats / r, ring_hits / r);
    std::printf("  leaf sizes:");
    for (int i = 0; i < 8; ++i) std::printf(" %d%s:%.2f", i, i == 7 ? "+" : "", leaf_hist[i] / r);
    std::printf("\n");
  }
  return 0;
}
