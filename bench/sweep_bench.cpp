// The sweep's speed: Kitchen 512x512, Whitted depth 4, DFL, 105 node-L1 points (7 sizes 1-64 KB
// x associativity 1, 2, 4, 8, full x lines 32, 64, 128 B, LRU), and the 60-point miss-ratio
// curve of one line size (12 sizes 1 KB-2 MB x the same associativities, 64 B lines), measured
// in one run against
//  - one `rtusim run` of the default point (8 KB, 4-way, 64 B): aim <= 2x its wall time;
//  - one run per point: the median of a few sampled points' runs times the point count;
//  - Dinero IV-style one configuration per pass over the same recorded node stream (a sample
//    of the configurations, each one SetAssocCache pass), against the sweep's one CacheSweep
//    pass over that stream for all of them: seconds per configuration, as a ratio.
// Wall times (medians of five, the run and the sweeps alternately) and the largest resident set
// of the child processes (getrusage of the children).
//
// usage: sweep_bench [WIDTH]   (default 512; the scene from $RTUSIM_SCENES)
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "app/pipeline.h"
#include "bench_timing.h"
#include "cache/set_assoc_cache.h"
#include "layout/layout_dispatch.h"
#include "scene/pinhole_camera.h"
#include "sweep/cache_sweep.h"
#include "tracer/whitted_tracer.h"
#include "traversal/traversal.h"
#include "util/error.h"

using namespace rtusim;
namespace fs = std::filesystem;
using rtusim::bench_timing::now_s;

namespace {

struct Measured {
  double seconds = 0;
  double max_rss_mb = 0;
};

// Runs argv to completion; its wall time and the largest resident set of it and its children.
Measured run_child(const std::vector<std::string>& argv) {
  std::fflush(stdout);  // or the child's freopen writes the buffer again
  const double t0 = now_s();
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> a;
    for (const auto& s : argv) a.push_back(const_cast<char*>(s.c_str()));
    a.push_back(nullptr);
    freopen("/dev/null", "w", stdout);
    execv(a[0], a.data());
    _exit(127);
  }
  int st = 0;
  rusage ru{};
  wait4(pid, &st, 0, &ru);
  if (!WIFEXITED(st) || WEXITSTATUS(st) != 0) throw std::runtime_error("failed: " + argv[0] + " " + argv[1]);
  rusage children{};
  getrusage(RUSAGE_CHILDREN, &children);
  return {now_s() - t0, std::max(ru.ru_maxrss, children.ru_maxrss) / 1024.0};
}

// Records the node stream of a frame: addresses as 32-bit image offsets (4 bytes per fetch).
class NodeRecorder final : public TraceBackend {
 public:
  explicit NodeRecorder(const MemoryImage& image) : image_(image) {}
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override {
    with_layout_decoder(image_, [&]<class Decoder>() {
      for (size_t i = 0; i < rays.size(); ++i)
        hits[i] = traverse<Decoder>(image_, rays[i].ray, rays[i].any_hit(), *this);
    });
  }
  void fetch(Stream s, uint64_t addr, uint32_t) {
    if (s == Stream::kNode) addrs.push_back(static_cast<uint32_t>(addr));
  }
  std::vector<uint32_t> addrs;

 private:
  const MemoryImage& image_;
};

}  // namespace

int main(int argc, char** argv) {
  try {
    const int width = argc > 1 ? std::stoi(argv[1]) : 512;
    const fs::path tmp = fs::temp_directory_path() / ("rtusim_sweep_bench_" + std::to_string(getpid()));
    fs::create_directories(tmp);
    const std::string rtusim =
        (fs::read_symlink("/proc/self/exe").parent_path().parent_path() / "rtusim").string();
    const std::string base =
        "[scene]\npath = \"$RTUSIM_SCENES/kitchen/kitchen.gltf\"\ncamera = \"bart_camera_t0\"\n"
        "[image]\nwidth = " + std::to_string(width) + "\nheight = " + std::to_string(width) +
        "\npng = false\nheatmaps = false\n[tracer]\nmax_depth = 4\n[layout]\nkind = \"dfl\"\n";
    std::ofstream(tmp / "base.toml") << base;
    std::ofstream(tmp / "spec.toml")
        << base << "[sweep]\nl1.line = [32, 64, 128]\nl1.assoc = [1, 2, 4, 8, \"full\"]\n"
        << "l1.size = [1024, 2048, 4096, 8192, 16384, 32768, 65536]\n";
    std::ofstream(tmp / "curve.toml")
        << base << "[sweep]\nl1.line = [64]\nl1.assoc = [1, 2, 4, 8, \"full\"]\n"
        << "l1.size = [1024, 2048, 4096, 8192, 16384, 32768, 65536, 131072, 262144, 524288, "
           "1048576, 2097152]\n";
    const int points = 105, curve_points = 60;
    std::printf("sweep_bench: kitchen %dx%d, Whitted depth 4, dfl, %d node-L1 points\n", width, width,
                points);

    // One run and the sweeps alternately, five times each (medians: the machine is shared).
    std::vector<double> one_s, sweep_s, curve_s;
    Measured one, sweep, curve;
    for (int rep = 0; rep < 5; ++rep) {
      const std::string r = std::to_string(rep);
      one = run_child({rtusim, "run", (tmp / "base.toml").string(), "--out", (tmp / ("run" + r)).string()});
      sweep = run_child({rtusim, "sweep", (tmp / "spec.toml").string(), "--out",
                         (tmp / ("sweep" + r)).string(), "--no-plots"});
      curve = run_child({rtusim, "sweep", (tmp / "curve.toml").string(), "--out",
                         (tmp / ("curve" + r)).string(), "--no-plots"});
      one_s.push_back(one.seconds);
      sweep_s.push_back(sweep.seconds);
      curve_s.push_back(curve.seconds);
    }
    one.seconds = bench_timing::median(one_s);
    sweep.seconds = bench_timing::median(sweep_s);
    curve.seconds = bench_timing::median(curve_s);
    std::vector<double> per_point;
    for (const char* set : {"l1.size=1024", "l1.assoc=1", "l1.line=128"})
      per_point.push_back(run_child({rtusim, "run", (tmp / "base.toml").string(), "--set", set,
                                     "--out", (tmp / ("p" + std::string(set))).string()})
                              .seconds);
    const double each = bench_timing::median(per_point);
    std::printf("  one rtusim run (default point, median of 5)   %8.2f s   max RSS %6.1f MB\n", one.seconds, one.max_rss_mb);
    std::printf("  rtusim sweep, %d points (median of 5, all cores) %8.2f s   max RSS %6.1f MB   %.2fx one run\n", points,
                sweep.seconds, sweep.max_rss_mb, sweep.seconds / one.seconds);
    std::printf("  rtusim sweep, %d points, 64 B lines, 1 KB-2 MB   %8.2f s   max RSS %6.1f MB   %.2fx one run\n",
                curve_points, curve.seconds, curve.max_rss_mb, curve.seconds / one.seconds);
    bench_timing::print_ratio("sweep_bench", "kitchen 105 points", "sweep", sweep.seconds,
                              "one run", one.seconds, "s");
    bench_timing::print_ratio("sweep_bench", "kitchen 60 points (64 B)", "sweep", curve.seconds,
                              "one run", one.seconds, "s");
    std::printf("  one run per point (median of 3 x %d) %7.1f s   the sweep is %.1fx faster\n", points,
                each * points, each * points / sweep.seconds);

    // Dinero IV-style: one configuration per pass over the recorded stream, against one pass.
    const Prepared p = prepare_run((tmp / "base.toml").string(), {});
    NodeRecorder rec(p.images.front());
    WhittedTracer tracer(p.scene, p.config.tracer, rec);
    tracer.render(PinholeCamera(p.camera, width, width), width, width);
    const auto& a = rec.addrs;
    std::vector<CacheParams> configs;
    for (const uint32_t line : {32u, 64u, 128u})
      for (const uint32_t assoc : {1u, 2u, 4u, 8u, 0u})
        for (uint64_t size = 1024; size <= 65536; size *= 2) {
          CacheParams c;
          c.line_bytes = line;
          c.size_bytes = size;
          c.assoc = assoc ? assoc : static_cast<uint32_t>(size / line);
          configs.push_back(c);
        }
    const uint32_t node_bytes = p.images.front().node_bytes;
    double t0 = now_s();
    CacheSweep all(configs, p.images.front().bytes.size());
    std::vector<SweepFetch> chunk;
    for (size_t i = 0; i < a.size(); i += 65536) {
      chunk.clear();
      for (size_t j = i; j < std::min(a.size(), i + 65536); ++j) chunk.push_back({a[j], node_bytes, 0});
      all.feed(chunk);
    }
    const double sweep_pass = now_s() - t0;
    double single_total = 0;
    int sampled = 0;
    for (size_t k = 0; k < configs.size(); k += 7, ++sampled) {
      t0 = now_s();
      SetAssocCache c(configs[k]);
      uint64_t m = 0;
      c.visit([&](auto& cache) {
        for (const uint32_t addr : a) m += cache.access_range(addr, node_bytes);
      });
      single_total += now_s() - t0;
      if (m != all.misses(k)[0]) throw std::logic_error("the sweep's misses differ");
    }
    const double single = single_total / sampled;
    std::printf("  stream: %zu node fetches, recorded at 4 B each (%.0f MB)\n", a.size(), a.size() * 4 / 1e6);
    std::printf("  one configuration per pass (mean of %d)  %6.3f s per configuration\n", sampled, single);
    std::printf("  one pass, %zu configurations            %6.3f s = %.4f s per configuration: %.1fx faster\n",
                configs.size(), sweep_pass, sweep_pass / configs.size(), single / (sweep_pass / configs.size()));
    fs::remove_all(tmp);
    return 0;
  } catch (const InputError& e) {
    std::fprintf(stderr, "sweep_bench: %s\n", e.what());
    return 2;
  }
}
