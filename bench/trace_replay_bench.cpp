// Replays a bin node trace through the 8 KB / 4-way / 64 B LRU node L1 the way `rtusim replay`
// does (replay_trace: 4 K-record chunks, repeat filter), and times, as CPU seconds (medians of
// 5), against the reference measured in the same run, the decode loop (the same chunked
// TraceReader::next() calls, no cache):
//  - replay_trace() in this process;
//  - the whole `rtusim replay` process (child CPU time: start-up, decode, replay, output).
// Also printed, for comparison only: decode() into one vector of every address (what this
// benchmark timed before; slower than streaming: a fresh 8 bytes/reference array each time).
//
// usage: trace_replay_bench [TRACE.bin]
// Without a trace it makes one through rtusim's library code: the built-in scene at 256x256,
// Whitted depth 4, recursive order, DFL (what `rtusim trace configs/default.toml --format bin`
// writes), in a temporary directory.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "app/pipeline.h"
#include "cache/set_assoc_cache.h"
#include "app/node_stream.h"
#include "app/trace_replay.h"
#include "trace/trace_format.h"
#include "util/error.h"
#include "bench_timing.h"

using namespace rtusim;
namespace fs = std::filesystem;

namespace {

using rtusim::bench_timing::median;
using rtusim::bench_timing::median_cpu_seconds;

constexpr int kReps = 5;

// The CPU seconds (user + system) of running argv to completion as a child process.
double child_cpu_seconds(const std::vector<std::string>& argv) {
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> a;
    for (const auto& x : argv) a.push_back(const_cast<char*>(x.c_str()));
    a.push_back(nullptr);
    if (!freopen("/dev/null", "w", stdout)) _exit(126);
    execv(a[0], a.data());
    _exit(127);
  }
  int st = 0;
  rusage ru{};
  wait4(pid, &st, 0, &ru);
  if (!WIFEXITED(st) || WEXITSTATUS(st) != 0) throw std::runtime_error("failed: " + argv[0]);
  const auto sec = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return sec(ru.ru_utime) + sec(ru.ru_stime);
}


// The default config's bin trace, written to `dir`.
fs::path make_trace(const fs::path& dir) {
  const fs::path cfg = dir / "bench.toml";
  std::ofstream(cfg) << "[scene]\npath = \"builtin:cornell\"\n[image]\nwidth = 256\nheight = 256\n"
                        "[tracer]\nmax_depth = 4\nray_order = \"recursive\"\n[layout]\nkind = \"dfl\"\n";
  const Prepared p = prepare_run(cfg.string(), {});
  const MemoryImage& image = p.images.front();
  const fs::path out = dir / "default_dfl.bin";
  const auto t0 = std::chrono::steady_clock::now();
  TraceWriter w(out, TraceFormat::kBin, image.layout, image.node_bytes, image_hash(image));
  write_node_stream(p, image, w);
  w.finish();
  std::printf("  generated %s: built-in scene 256x256, dfl, %.2f s (trace + write)\n",
              out.string().c_str(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return out;
}

volatile uint64_t g_sink;

}  // namespace

int main(int argc, char** argv) {
  try {
    fs::path tmp;
    fs::path path;
    std::printf("trace_replay_bench: median of %d\n", kReps);
    if (argc > 1) {
      path = argv[1];
    } else {
      tmp = fs::temp_directory_path() / ("rtusim_trace_bench_" + std::to_string(::getpid()));
      fs::create_directories(tmp);
      path = make_trace(tmp);
    }
    // The reference: the chunked decode loop replay_trace() runs, without the cache.
    uint64_t refs = 0;
    const double decode_s = median_cpu_seconds(kReps, [&] {
      TraceReader reader(path);
      std::vector<uint64_t> addrs;
      std::vector<uint32_t> sizes;
      uint64_t n = 0, sum = 0;
      while (reader.next(addrs, sizes, kReplayChunkRecords)) {
        n += addrs.size();
        for (const uint64_t x : addrs) sum += x;
      }
      refs = n;
      g_sink = sum;
    });
    const TraceReader first(path);
    const TraceHeader& h = first.header();
    const double n = static_cast<double>(refs);
    std::printf("  trace     %s: %llu references, %s, layout %s, %.2f bytes/reference\n",
                path.string().c_str(), static_cast<unsigned long long>(refs),
                h.format == TraceFormat::kBin ? "bin" : "din", h.layout.c_str(),
                h.format == TraceFormat::kBin ? double(h.payload_bytes) / n : 0.0);

    const CacheParams params;  // 8 KB, 4-way, 64 B, lru
    TraceReplayCounts counts;
    const double replay_s = median_cpu_seconds(kReps, [&] {
      TraceReader reader(path);
      counts = replay_trace(reader, params);
    });
    const double vector_s = median_cpu_seconds(kReps, [&] { g_sink = first.decode().size(); });
    const std::string rtusim =
        (fs::read_symlink("/proc/self/exe").parent_path().parent_path() / "rtusim").string();
    std::vector<double> process;
    for (int i = 0; i < kReps; ++i) process.push_back(child_cpu_seconds({rtusim, "replay", path.string()}));
    const double process_s = median(process);

    std::printf("  %-34s %8.1f Mref/s (CPU)\n", "decode loop (reference)", n / decode_s / 1e6);
    std::printf("  %-34s %8.1f Mref/s (CPU)   %.2fx decode time; %llu misses (%.3f%%)\n",
                "replay_trace 8K/4-way/64B LRU", n / replay_s / 1e6, replay_s / decode_s,
                static_cast<unsigned long long>(counts.misses),
                100.0 * double(counts.misses) / double(counts.accesses));
    std::printf("  %-34s %8.1f Mref/s (CPU)   %.2fx decode time\n", "rtusim replay, whole process",
                n / process_s / 1e6, process_s / decode_s);
    std::printf("  %-34s %8.1f Mref/s (CPU)   (not the replay path)\n", "decode() into one vector",
                n / vector_s / 1e6);
    rtusim::bench_timing::print_ratio("trace_replay_bench", "decode + 8K/4-way/64B LRU",
                                      "replay_trace", n / replay_s / 1e6, "decode loop",
                                      n / decode_s / 1e6, "Mref/s");
    rtusim::bench_timing::print_ratio("trace_replay_bench", "rtusim replay process (CPU)",
                                      "rtusim replay", n / process_s / 1e6, "decode loop",
                                      n / decode_s / 1e6, "Mref/s");
    if (!tmp.empty()) fs::remove_all(tmp);
    return 0;
  } catch (const InputError& e) {
    std::fprintf(stderr, "trace_replay_bench: %s\n", e.what());
    return 2;
  }
}
