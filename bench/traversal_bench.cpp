// Single-thread primary-ray throughput of the host kd-tree traversal against Embree's
// rtcIntersect1 on the same rays in the same run, plus kd-tree build time and memory.
// Usage: traversal_bench [--verify] [SCENE ...]  (names under $RTUSIM_SCENES; default sponza and
// kitchen). Always prints, on stderr, a hash of the DFL hits and of their fetch stream (every
// node, list and triangle fetch in issue order): a faster traversal must leave both unchanged.
// --verify prints the same for every layout and skips the timing.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "bench_timing.h"
#include "app/run_config.h"
#include "embree_scene.h"
#include "kdtree/sah_builder.h"
#include "layout/dfl_layout.h"
#include "layout/layout.h"
#include "layout/layout_dispatch.h"
#include "scene/gltf_loader.h"
#include "scene/pinhole_camera.h"
#include "traversal/traversal.h"

using namespace rtusim;

namespace {

using rtusim::bench_timing::cpu_s;
using rtusim::bench_timing::median;

// FNV-1a over 64-bit words.
struct Fnv {
  uint64_t h = 1469598103934665603ull;
  void add(uint64_t w) {
    for (int i = 0; i < 8; ++i) h = (h ^ ((w >> (8 * i)) & 0xff)) * 1099511628211ull;
  }
};

// A fetch sink that hashes the fetch stream and counts node visits.
struct HashSink {
  Fnv fnv;
  uint64_t node_fetches = 0, fetches = 0;
  void fetch(Stream s, uint64_t addr, uint32_t bytes) {
    fnv.add((uint64_t{static_cast<uint8_t>(s)} << 56) ^ (uint64_t{bytes} << 40) ^ addr);
    node_fetches += s == Stream::kNode;
    ++fetches;
  }
};

// Prints the hash of every hit (t, triangle, barycentrics, bit for bit) and of the fetch stream
// of `rays` traced closest-hit and then any-hit through the image's layout.
void print_hashes(const std::string& scene, const MemoryImage& image, const std::vector<Ray>& rays) {
  Fnv hits;
  HashSink sink;
  with_layout_decoder(image, [&]<class D>() {
    for (const bool any_hit : {false, true})
      for (const Ray& ray : rays) {
        const Hit h = traverse<D>(image, ray, any_hit, sink);
        uint32_t t, u, v;
        std::memcpy(&t, &h.t, 4);
        std::memcpy(&u, &h.u, 4);
        std::memcpy(&v, &h.v, 4);
        hits.add((uint64_t{t} << 32) | h.triangle);
        hits.add((uint64_t{u} << 32) | v);
      }
  });
  std::fprintf(stderr, "verify %s %s hits %016llx fetches %llu (nodes %llu) stream %016llx\n",
               scene.c_str(), image.layout.c_str(), (unsigned long long)hits.h,
               (unsigned long long)sink.fetches, (unsigned long long)sink.node_fetches,
               (unsigned long long)sink.fnv.h);
}

double max_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> scenes;
  bool verify = false;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--verify")
      verify = true;
    else
      scenes.push_back(argv[i]);
  }
  if (scenes.empty()) scenes = {"sponza_dabrovic", "kitchen"};
  const int w = 512, h = 512, reps = 5;

  if (!verify)
    std::printf("%-20s %9s %8s %9s %9s %10s %10s %7s\n", "scene", "tris", "build_s", "nodes",
                "rss_MB", "kd_Mray/s", "emb_Mray/s", "ratio");
  for (const std::string& name : scenes) {
    const Scene scene = load_gltf(scenes_dir() + "/" + name + "/" + name + ".gltf");
    const double rss0 = max_rss_mb();
    std::vector<double> build_times;
    KdTree tree;
    for (int r = 0; r < 3; ++r) {
      tree = build_sah_kd_tree(scene, KdBuildParams{});
      build_times.push_back(tree.report.build_seconds);
    }
    const double rss_build = max_rss_mb() - rss0;
    const MemoryImage image = DflLayout().build_image(tree, scene);
    oracle::EmbreeScene embree(scene);

    std::vector<Ray> rays;
    const PinholeCamera cam(scene.cameras.front(), w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) rays.push_back(cam.generate(x, y));
    if (verify) {
      for (const std::string& kind : layout_kinds())
        print_hashes(name, make_layout(kind)->build_image(tree, scene), rays);
      continue;
    }
    print_hashes(name, image, rays);

    // Interleave the two so machine noise hits both alike; checksums keep the work alive.
    std::vector<double> kd_rate, emb_rate;
    double checksum = 0.0;
    for (int r = 0; r < reps; ++r) {
      NullFetchSink sink;
      double t0 = cpu_s();
      for (const Ray& ray : rays) checksum += traverse<DflLayout>(image, ray, false, sink).triangle;
      kd_rate.push_back(rays.size() / (cpu_s() - t0));
      t0 = cpu_s();
      for (const Ray& ray : rays) checksum += embree.intersect(ray).triangle;
      emb_rate.push_back(rays.size() / (cpu_s() - t0));
    }
    std::printf("%-20s %9u %8.3f %9llu %9.1f %10.2f %10.2f %7.2f\n", name.c_str(),
                scene.triangle_count(), median(build_times),
                (unsigned long long)tree.report.nodes, rss_build, median(kd_rate) / 1e6,
                median(emb_rate) / 1e6, median(kd_rate) / median(emb_rate));
    std::fprintf(stderr, "checksum %g\n", checksum);
    bench_timing::print_ratio("traversal_bench", (name + " 512x512 primary").c_str(),
                              "kd-tree traversal", median(kd_rate) / 1e6,
                              "Embree rtcIntersect1", median(emb_rate) / 1e6, "Mrays/s");
  }
  if (!verify)
    std::printf("(medians of %d runs; ratio = kd-tree rays/s / Embree rtcIntersect1 rays/s, 1 "
                "thread, thread CPU time; rss_MB = growth of peak RSS during the builds)\n",
                reps);
  return 0;
}
