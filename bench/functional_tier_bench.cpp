// Functional tier speed: node fetches per second through the cache model, and its slowdown
// against traversing the same rays with no cache model, measured in the same run.
// Usage: functional_tier_bench [CONFIG [--set KEY=VALUE]...]   (default configs/sponza_dabrovic.toml)
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_timing.h"
#include "app/pipeline.h"
#include "cache/fetch_cache.h"
#include "layout/layout_dispatch.h"
#include "tracer/host_backend.h"
#include "tracer/whitted_tracer.h"
#include "traversal/traversal.h"

using namespace rtusim;

namespace {

using rtusim::bench_timing::median;

// Records every ray the tracer issues, in order, while the host backend traces it.
class RecordingBackend final : public TraceBackend {
 public:
  explicit RecordingBackend(const MemoryImage& image) : host_(image) {}
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override {
    host_.trace(rays, hits);
    log.insert(log.end(), rays.begin(), rays.end());
  }
  std::vector<RayRecord> log;

 private:
  HostBackend host_;
};


}  // namespace

int main(int argc, char** argv) {
  const std::string config = argc > 1 ? argv[1] : RTUSIM_BENCH_SOURCE_DIR "/configs/sponza_dabrovic.toml";
  std::vector<std::string> overrides;
  for (int i = 2; i + 1 < argc; i += 2)
    if (std::string(argv[i]) == "--set") overrides.push_back(argv[i + 1]);
  const Prepared p = prepare_run(config, overrides);
  const MemoryImage& image = p.images.front();

  RecordingBackend rec(image);
  WhittedTracer tracer(p.scene, p.config.tracer, rec);
  tracer.render(PinholeCamera(p.camera, p.config.image.width, p.config.image.height),
                p.config.image.width, p.config.image.height);
  const std::vector<RayRecord>& rays = rec.log;

  const int reps = 5;
  std::vector<double> plain_s, cached_s;
  uint64_t node_fetches = 0, misses = 0, checksum = 0;
  with_layout_decoder(image, [&]<class Decoder>() {
    for (int r = 0; r < reps; ++r) {
      double t0 = bench_timing::cpu_s();
      NullFetchSink none;
      for (const RayRecord& ray : rays) checksum += traverse<Decoder>(image, ray.ray, ray.any_hit(), none).triangle;
      plain_s.push_back(bench_timing::cpu_s() - t0);
      FetchCache caches(p.config.fetch_caches());
      t0 = bench_timing::cpu_s();
      caches.with_inlined_node_l1([&](auto& sink) {
        for (const RayRecord& ray : rays) checksum += traverse<Decoder>(image, ray.ray, ray.any_hit(), sink).triangle;
      });
      cached_s.push_back(bench_timing::cpu_s() - t0);
      node_fetches = caches.stream(Stream::kNode).fetches;
      misses = caches.stream(Stream::kNode).misses;
    }
  });
  const double plain = median(plain_s), cached = median(cached_s);
  std::printf("%s (%s): %zu rays, %llu node fetches, %llu L1 misses\n", config.c_str(),
              image.layout.c_str(), rays.size(), (unsigned long long)node_fetches,
              (unsigned long long)misses);
  std::printf("  plain traversal   %.3f s  %.1f M node visits/s\n", plain, node_fetches / plain / 1e6);
  std::printf("  functional tier   %.3f s  %.1f M node fetches/s\n", cached, node_fetches / cached / 1e6);
  std::printf("  slowdown          %.2fx   (medians of %d, thread CPU time; checksum %llu)\n",
              cached / plain, reps, (unsigned long long)checksum);
  const std::string case_name = std::filesystem::path(config).stem().string() + " Whitted " +
                                std::to_string(p.config.image.width) + "x" +
                                std::to_string(p.config.image.height) + " " + image.layout;
  bench_timing::print_ratio("functional_tier_bench", case_name.c_str(), "functional tier", cached,
                            "plain traversal", plain, "s");
  return 0;
}
