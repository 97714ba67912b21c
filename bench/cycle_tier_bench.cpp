// Speed of the SystemC cycle tier against plain traversal of the same rays in the same run:
// node fetches simulated per second and the slowdown (medians). SystemC elaborates once per
// process, so every cycle-tier run is a forked child that reports through a pipe.
// Usage: cycle_tier_bench [RUNS]   (sponza too when $RTUSIM_SCENES holds sponza_dabrovic)
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "bench_timing.h"
#include "app/run_config.h"
#include "kdtree/sah_builder.h"
#include "layout/layout.h"
#include "layout/layout_dispatch.h"
#include "model/cycle_backend.h"
#include "scene/builtin_scene.h"
#include "scene/gltf_loader.h"
#include "scene/pinhole_camera.h"
#include "traversal/traversal.h"
#include "util/stats.h"

using namespace rtusim;

namespace {

using rtusim::bench_timing::cpu_s;
using rtusim::bench_timing::median;


struct CycleRun {
  double seconds = 0;
  double cycles = 0, node_fetches = 0, dram_bytes = 0, l1_miss_rate = 0, gbps = 0, util = 0;
};

// One cycle-tier run in a child process.
CycleRun run_cycle_tier(const MemoryImage& image, const std::vector<RayRecord>& rays) {
  int fd[2];
  if (pipe(fd) != 0) std::abort();
  const pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    CycleRun r;
    CycleParams p;
    p.finish();
    CycleBackend backend(image, p);
    std::vector<Hit> hits(rays.size());
    const double t0 = cpu_s();
    backend.trace(rays, hits);
    r.seconds = cpu_s() - t0;
    Stats s;
    backend.write_stats(s);
    r.cycles = s.at("sim.cycles").get<double>();
    r.node_fetches = s.at("traversal.node_fetches").get<double>();
    r.dram_bytes = s.at("dram.bytes.total").get<double>();
    r.l1_miss_rate = s.at("l1.misses").get<double>() / s.at("l1.accesses").get<double>();
    r.gbps = s.at("dram.gbytes_per_second").get<double>();
    r.util = s.at("unit.utilisation").get<double>();
    if (write(fd[1], &r, sizeof r) != sizeof r) _exit(1);
    _exit(0);
  }
  close(fd[1]);
  CycleRun r;
  const ssize_t n = read(fd[0], &r, sizeof r);
  close(fd[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (n != sizeof r || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::fprintf(stderr, "cycle-tier child failed\n");
    std::exit(1);
  }
  return r;
}

void bench(const std::string& name, const Scene& scene, std::vector<RayRecord> rays, int runs) {
  const KdTree tree = build_sah_kd_tree(scene, KdBuildParams{});
  const MemoryImage image = make_layout("dfl")->build_image(tree, scene);
  std::vector<double> plain, cyc;
  CycleRun last;
  double checksum = 0;
  for (int r = 0; r < runs; ++r) {
    const double t0 = cpu_s();
    with_layout_decoder(image, [&]<class Decoder>() {
      NullFetchSink sink;
      for (const RayRecord& rr : rays)
        checksum += traverse<Decoder>(image, rr.ray, rr.any_hit(), sink).triangle;
    });
    plain.push_back(cpu_s() - t0);
    last = run_cycle_tier(image, rays);
    cyc.push_back(last.seconds);
  }
  const double plain_s = median(plain), cyc_s = median(cyc);
  std::printf("%-22s %8zu %10.0f %9.4f %9.4f %8.1f %10.2f %11.0f %7.3f %7.2f %5.2f\n",
              name.c_str(), rays.size(), last.node_fetches, plain_s, cyc_s, cyc_s / plain_s,
              last.node_fetches / cyc_s / 1e6, last.cycles, last.l1_miss_rate, last.gbps,
              last.util);
  std::fprintf(stderr, "checksum %g\n", checksum);
  bench_timing::print_ratio("cycle_tier_bench", name.c_str(), "cycle tier", cyc_s,
                            "plain traversal", plain_s, "s");
}

std::vector<RayRecord> primary_rays(const Scene& scene, int w, int h) {
  std::vector<RayRecord> rays;
  const PinholeCamera cam(scene.cameras.front(), w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      RayRecord r;
      r.ray = cam.generate(x, y);
      r.pixel = static_cast<uint32_t>(y * w + x);
      rays.push_back(r);
    }
  return rays;
}

// Incoherent rays: random origins inside the scene's bounds, random directions.
void add_random_rays(const Scene& scene, int n, std::vector<RayRecord>& rays) {
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const glm::vec3& p : scene.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f), d(-1.0f, 1.0f);
  for (int i = 0; i < n; ++i) {
    RayRecord r;
    r.ray.origin = lo + (hi - lo) * glm::vec3(u(rng), u(rng), u(rng));
    r.ray.dir = glm::vec3(d(rng), d(rng), d(rng));
    r.kind = i % 2 ? RayKind::kShadow : RayKind::kReflection;
    rays.push_back(r);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  std::printf("%-22s %8s %10s %9s %9s %8s %10s %11s %7s %7s %5s\n", "scene", "rays", "nodes",
              "plain_s", "cycle_s", "slowdown", "Mnode/s", "sim_cycles", "l1_miss", "GB/s", "util");
  {
    const Scene cornell = make_builtin_scene("cornell");
    std::vector<RayRecord> rays = primary_rays(cornell, 256, 256);
    add_random_rays(cornell, 4096, rays);
    bench("cornell 256x256+4096", cornell, std::move(rays), runs);
  }
  const std::string sponza = scenes_dir() + "/sponza_dabrovic/sponza_dabrovic.gltf";
  if (std::filesystem::exists(sponza)) {
    const Scene scene = load_gltf(sponza);
    bench("sponza 256x256", scene, primary_rays(scene, 256, 256), runs);
  } else {
    std::printf("(no %s: sponza skipped)\n", sponza.c_str());
  }
  std::printf("(medians of %d runs, thread CPU time; slowdown = cycle tier / plain traversal "
              "(NullFetchSink) of the same rays; Mnode/s = node fetches simulated per second; defaults: 32 rays in "
              "flight, 8 KB 4-way L1, 8 MSHRs, DDR4-2400, lists/triangles straight to DRAM)\n",
              runs);
  return 0;
}
