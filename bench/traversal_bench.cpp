// Single-thread primary-ray throughput of the host kd-tree traversal, ray by ray (traverse())
// and in packets (traverse_batch(): 8 lanes with AVX2 or AVX-512; 16x1 strips of the scan
// order, and 4x4 tiles), against Embree's rtcIntersect1 and its own 16-ray packets
// (rtcIntersect16 on the same groups)
// on the same rays in the same run, plus kd-tree build time and memory.
// Usage: traversal_bench [--verify] [SCENE ...]  (names under $RTUSIM_SCENES; default sponza and
// kitchen). Always prints, on stderr, a hash of the DFL hits and of their fetch stream (every
// node, list and triangle fetch in issue order), ray by ray and batched: a faster traversal must
// leave both unchanged, and the two must agree. --verify prints the same for every layout, skips
// the timing, and exits 1 if the batched hashes differ from the ray-by-ray ones.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <type_traits>
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
#include "traversal/batch_traversal.h"
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

// A batch record for traverse_batch(): a ray, closest-hit or any-hit.
struct Record {
  Ray ray;
  bool shadow = false;
  bool any_hit() const { return shadow; }
};

// Hashes of a run: every hit (t, triangle, barycentrics, bit for bit) and the fetch stream.
struct RunHashes {
  Fnv hits;
  HashSink sink;
  void add(const Hit& h) {
    uint32_t t, u, v;
    std::memcpy(&t, &h.t, 4);
    std::memcpy(&u, &h.u, 4);
    std::memcpy(&v, &h.v, 4);
    hits.add((uint64_t{t} << 32) | h.triangle);
    hits.add((uint64_t{u} << 32) | v);
  }
  bool operator==(const RunHashes& o) const {
    return hits.h == o.hits.h && sink.fnv.h == o.sink.fnv.h && sink.fetches == o.sink.fetches;
  }
  void print(const std::string& scene, const MemoryImage& image, const char* how) const {
    std::fprintf(stderr, "verify %s %s%s hits %016llx fetches %llu (nodes %llu) stream %016llx\n",
                 scene.c_str(), image.layout.c_str(), how, (unsigned long long)hits.h,
                 (unsigned long long)sink.fetches, (unsigned long long)sink.node_fetches,
                 (unsigned long long)sink.fnv.h);
  }
};

// Prints the hashes of `rays` traced closest-hit and then any-hit through the image's layout,
// ray by ray and batched; returns whether the two agree.
bool print_hashes(const std::string& scene, const MemoryImage& image, const std::vector<Ray>& rays) {
  RunHashes single, batched;
  with_layout_decoder(image, [&]<class D>() {
    std::vector<Record> records(rays.size());
    std::vector<Hit> hits(rays.size());
    for (const bool any_hit : {false, true}) {
      for (const Ray& ray : rays) single.add(traverse<D>(image, ray, any_hit, single.sink));
      for (size_t i = 0; i < rays.size(); ++i) records[i] = {rays[i], any_hit};
      traverse_batch<D>(image, std::span<const Record>(records), std::span<Hit>(hits),
                        batched.sink);
      for (const Hit& h : hits) batched.add(h);
    }
  });
  single.print(scene, image, "");
  batched.print(scene, image, " batched");
  const bool same = single == batched;
  if (!same) std::fprintf(stderr, "MISMATCH %s %s: batched != ray by ray\n", scene.c_str(),
                          image.layout.c_str());
  return same;
}

// Whether the batched traversal of the rays in 4x4 tiles gives every ray its own hit.
bool check_tiles(const MemoryImage& image, const std::vector<Ray>& rays,
                 const std::vector<Record>& tiles, int w, int h) {
  std::vector<Hit> hits(tiles.size());
  NullFetchSink none;
  traverse_batch<DflLayout>(image, std::span<const Record>(tiles), std::span<Hit>(hits), none);
  size_t k = 0;
  for (int ty = 0; ty < h; ty += 4)
    for (int tx = 0; tx < w; tx += 4)
      for (int y = ty; y < ty + 4; ++y)
        for (int x = tx; x < tx + 4; ++x, ++k) {
          const Hit a = traverse<DflLayout>(image, rays[size_t(y) * w + x], false, none);
          if (std::memcmp(&a, &hits[k], sizeof a) != 0) {
            std::fprintf(stderr, "MISMATCH %s: 4x4-tile packets, pixel %d %d\n",
                         image.layout.c_str(), x, y);
            return false;
          }
        }
  return true;
}

// The host's packets as the RATIO lines name them: "16-ray packets", "8-ray packets", or ray by
// ray where the build has none.
std::string packet_label() {
  if constexpr (std::is_void_v<HostRayPacket>) return "ray by ray (no packets)";
  else return std::to_string(HostRayPacket::kLanes) + "-ray packets";
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

  bool all_same = true;
  if (!verify)
    std::printf("%-20s %9s %8s %9s %9s %10s %10s %10s %10s %7s %7s %7s\n", "scene", "tris",
                "build_s", "nodes", "rss_MB", "kd_Mray/s", "pkt_Mray/s", "emb_Mray/s",
                "e16_Mray/s", "ratio", "pkt/emb", "pkt/e16");
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
        all_same &= print_hashes(name, make_layout(kind)->build_image(tree, scene), rays);
      continue;
    }
    all_same &= print_hashes(name, image, rays);

    // Interleave the four so machine noise hits all alike; checksums keep the work alive.
    std::vector<Record> records(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) records[i] = {rays[i], false};
    // The same rays in 4x4 tiles (tile after tile in scan order), for packets of both kinds.
    std::vector<Ray> tile_rays;
    for (int ty = 0; ty < h; ty += 4)
      for (int tx = 0; tx < w; tx += 4)
        for (int y = ty; y < ty + 4; ++y)
          for (int x = tx; x < tx + 4; ++x) tile_rays.push_back(rays[size_t(y) * w + x]);
    std::vector<Record> tile_records(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) tile_records[i] = {tile_rays[i], false};
    std::vector<Hit> hits(rays.size());
    all_same &= check_tiles(image, rays, tile_records, w, h);
    std::vector<double> kd_rate, pkt_rate, emb_rate, e16_rate, tile_rate, e16_tile_rate;
    double checksum = 0.0;
    for (int r = 0; r < reps; ++r) {
      NullFetchSink sink;
      double t0 = cpu_s();
      for (const Ray& ray : rays) checksum += traverse<DflLayout>(image, ray, false, sink).triangle;
      kd_rate.push_back(rays.size() / (cpu_s() - t0));
      t0 = cpu_s();
      traverse_batch<DflLayout>(image, std::span<const Record>(records), std::span<Hit>(hits),
                                sink);
      for (const Hit& hit : hits) checksum += hit.triangle;
      pkt_rate.push_back(rays.size() / (cpu_s() - t0));
      t0 = cpu_s();
      for (const Ray& ray : rays) checksum += embree.intersect(ray).triangle;
      emb_rate.push_back(rays.size() / (cpu_s() - t0));
      t0 = cpu_s();
      for (size_t b = 0; b < rays.size(); b += 16) {
        const int n = static_cast<int>(std::min<size_t>(16, rays.size() - b));
        embree.intersect16(rays.data() + b, n, hits.data() + b);
      }
      for (const Hit& hit : hits) checksum += hit.triangle;
      e16_rate.push_back(rays.size() / (cpu_s() - t0));
      t0 = cpu_s();
      traverse_batch<DflLayout>(image, std::span<const Record>(tile_records),
                                std::span<Hit>(hits), sink);
      for (const Hit& hit : hits) checksum += hit.triangle;
      tile_rate.push_back(rays.size() / (cpu_s() - t0));
      t0 = cpu_s();
      for (size_t b = 0; b < rays.size(); b += 16)
        embree.intersect16(tile_rays.data() + b, 16, hits.data() + b);
      for (const Hit& hit : hits) checksum += hit.triangle;
      e16_tile_rate.push_back(rays.size() / (cpu_s() - t0));
    }
    const double kd = median(kd_rate) / 1e6, pkt = median(pkt_rate) / 1e6;
    const double emb = median(emb_rate) / 1e6, e16 = median(e16_rate) / 1e6;
    const double tile = median(tile_rate) / 1e6, e16_tile = median(e16_tile_rate) / 1e6;
    std::printf("%-20s %9u %8.3f %9llu %9.1f %10.2f %10.2f %10.2f %10.2f %7.2f %7.2f %7.2f\n",
                name.c_str(), scene.triangle_count(), median(build_times),
                (unsigned long long)tree.report.nodes, rss_build, kd, pkt, emb, e16, kd / emb,
                pkt / emb, pkt / e16);
    std::fprintf(stderr, "checksum %g\n", checksum);
    const std::string case_name = name + " 512x512 primary";
    const std::string packets = "kd-tree traversal, " + packet_label();
    bench_timing::print_ratio("traversal_bench", case_name.c_str(), "kd-tree traversal", kd,
                              "Embree rtcIntersect1", emb, "Mrays/s");
    bench_timing::print_ratio("traversal_bench", case_name.c_str(),
                              packets.c_str(), pkt, "Embree rtcIntersect1",
                              emb, "Mrays/s");
    bench_timing::print_ratio("traversal_bench", case_name.c_str(),
                              packets.c_str(), pkt,
                              "Embree rtcIntersect16", e16, "Mrays/s");
    bench_timing::print_ratio("traversal_bench", case_name.c_str(),
                              (packets + " of 4x4 tiles").c_str(), tile,
                              "Embree rtcIntersect1", emb, "Mrays/s");
    bench_timing::print_ratio("traversal_bench", case_name.c_str(),
                              (packets + " of 4x4 tiles").c_str(), tile,
                              "Embree rtcIntersect16, 4x4 tiles", e16_tile, "Mrays/s");
  }
  if (!verify)
    std::printf("(medians of %d runs; ratio = kd-tree rays/s / Embree rtcIntersect1 rays/s, "
                "pkt = kd-tree %s (16x1 strips), e16 = Embree rtcIntersect16 on the "
                "same strips (4x4 tiles: the RATIO lines); 1 thread, thread CPU time; rss_MB = growth of peak RSS during the "
                "builds)\n",
                reps, packet_label().c_str());
  return all_same ? 0 : 1;
}
