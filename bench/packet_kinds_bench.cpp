// The host traversal's packets (traverse_batch(); 8 lanes with AVX2 or AVX-512) against
// ray by ray (traverse()) on the ray batches of a Whitted wavefront frame, by kind: primary,
// shadow, secondary (reflection and refraction); with no fetch sink, and recording every fetch
// in a FetchLog as the parallel functional tier does (packets: each ray's fetches buffered, then
// handed to the log in ray order; that costs more than the packets save, so the functional tier
// records ray by ray).
// Usage: packet_kinds_bench [SCENE ...]  (names under $RTUSIM_SCENES; default sponza and kitchen)
#include <cstdio>
#include <string>
#include <type_traits>
#include <vector>

#include "app/run_config.h"
#include "bench_timing.h"
#include "kdtree/sah_builder.h"
#include "layout/dfl_layout.h"
#include "scene/gltf_loader.h"
#include "scene/pinhole_camera.h"
#include "tracer/fetch_log.h"
#include "tracer/whitted_tracer.h"
#include "traversal/batch_traversal.h"

using namespace rtusim;

namespace {

using rtusim::bench_timing::cpu_s;
using rtusim::bench_timing::median;

// Keeps every batch the tracer hands out (and answers it ray by ray).
class CapturingBackend final : public TraceBackend {
 public:
  explicit CapturingBackend(const MemoryImage& image) : image_(image) {}
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override {
    NullFetchSink none;
    for (size_t i = 0; i < rays.size(); ++i)
      hits[i] = traverse<DflLayout>(image_, rays[i].ray, rays[i].any_hit(), none);
    batches.emplace_back(rays.begin(), rays.end());
  }
  std::vector<std::vector<RayRecord>> batches;

 private:
  const MemoryImage& image_;
};

// The fetch log sink of the parallel functional tier (tracer/parallel_render.cpp).
struct LogSink {
  FetchLog& log;
  std::span<const RayRecord> rays;
  void fetch(Stream s, uint64_t addr, uint32_t bytes) { log.fetch(s, addr, bytes); }
  void end_ray(size_t i) { log.end_ray(rays[i]); }
};

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> scenes(argv + 1, argv + argc);
  if (scenes.empty()) scenes = {"sponza_dabrovic", "kitchen"};
  const int w = 512, h = 512, reps = 5;
  std::string packets = "kd-tree ray by ray (no packets)";  // the RATIO lines' name
  if constexpr (!std::is_void_v<HostRayPacket>)
    packets = "kd-tree " + std::to_string(HostRayPacket::kLanes) + "-ray packets";
  std::printf("%-16s %-10s %9s %9s %9s %7s %9s %9s %7s\n", "scene", "kind", "rays", "1_Mray/s",
              "pkt_Mray/s", "ratio", "1log_Mr/s", "pklog_Mr/s", "ratio");
  for (const std::string& name : scenes) {
    const Scene scene = load_gltf(scenes_dir() + "/" + name + "/" + name + ".gltf");
    const KdTree tree = build_sah_kd_tree(scene, KdBuildParams{});
    const MemoryImage image = DflLayout().build_image(tree, scene);
    TracerParams params;
    params.order = RayOrder::kWavefront;
    CapturingBackend capture(image);
    WhittedTracer(scene, params, capture).render(PinholeCamera(scene.cameras.front(), w, h), w, h);

    // Batches by kind: the first is the primary rays; shadow batches hold only shadow rays.
    const char* kinds[] = {"primary", "shadow", "secondary"};
    std::vector<std::vector<std::vector<RayRecord>>> by_kind(3);
    for (size_t b = 0; b < capture.batches.size(); ++b) {
      const auto& batch = capture.batches[b];
      if (batch.empty()) continue;
      const int k = b == 0 ? 0 : batch.front().kind == RayKind::kShadow ? 1 : 2;
      by_kind[k].push_back(batch);
    }
    for (int k = 0; k < 3; ++k) {
      size_t rays = 0;
      for (const auto& b : by_kind[k]) rays += b.size();
      if (rays == 0) continue;
      std::vector<double> one, pkt, one_log, pkt_log;
      std::vector<Hit> hits;
      double checksum = 0.0;
      FetchLog log;
      for (int r = 0; r < reps; ++r) {
        NullFetchSink none;
        double t0 = cpu_s();
        for (const auto& b : by_kind[k])
          for (const RayRecord& rr : b)
            checksum += traverse<DflLayout>(image, rr.ray, rr.any_hit(), none).triangle;
        one.push_back(rays / (cpu_s() - t0));
        t0 = cpu_s();
        for (const auto& b : by_kind[k]) {
          hits.resize(b.size());
          traverse_batch<DflLayout>(image, std::span<const RayRecord>(b), std::span<Hit>(hits),
                                    none);
          checksum += hits.empty() ? 0 : hits.front().triangle;
        }
        pkt.push_back(rays / (cpu_s() - t0));
        // With the log, in chunks of 256 rays as ParallelBackend traces them.
        t0 = cpu_s();
        for (const auto& b : by_kind[k])
          for (size_t c = 0; c < b.size(); c += 256) {
            log.clear();
            for (size_t i = c; i < std::min(b.size(), c + 256); ++i) {
              checksum += traverse<DflLayout>(image, b[i].ray, b[i].any_hit(), log).triangle;
              log.end_ray(b[i]);
            }
          }
        one_log.push_back(rays / (cpu_s() - t0));
        t0 = cpu_s();
        for (const auto& b : by_kind[k])
          for (size_t c = 0; c < b.size(); c += 256) {
            log.clear();
            const auto part = std::span<const RayRecord>(b).subspan(c, std::min<size_t>(256, b.size() - c));
            hits.resize(part.size());
            LogSink sink{log, part};
            traverse_batch<DflLayout>(image, part, std::span<Hit>(hits), sink);
            checksum += hits.front().triangle;
          }
        pkt_log.push_back(rays / (cpu_s() - t0));
      }
      std::fprintf(stderr, "checksum %g\n", checksum);
      std::printf("%-16s %-10s %9zu %9.2f %9.2f %7.2f %9.2f %9.2f %7.2f\n", name.c_str(),
                  kinds[k], rays, median(one) / 1e6, median(pkt) / 1e6, median(pkt) / median(one),
                  median(one_log) / 1e6, median(pkt_log) / 1e6, median(pkt_log) / median(one_log));
      const std::string case_name = name + " 512x512 wavefront " + kinds[k];
      bench_timing::print_ratio("packet_kinds_bench", case_name.c_str(),
                                packets.c_str(), median(pkt) / 1e6,
                                "kd-tree ray by ray", median(one) / 1e6, "Mrays/s");
    }
  }
  std::printf("(medians of %d runs, 1 thread, thread CPU time; ratio = packets / ray by ray; "
              "log: recording every fetch in a FetchLog, 256-ray chunks)\n",
              reps);
  return 0;
}
