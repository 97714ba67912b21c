// Replays a bin node trace through the 8 KB / 4-way / 64 B LRU node L1 and prints the median
// references/s of 5 repetitions, with the decode-only rate (varint deltas + checksum, no cache)
// measured in the same run as the reference.
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

#include <unistd.h>

#include "app/pipeline.h"
#include "cache/set_assoc_cache.h"
#include "app/node_stream.h"
#include "trace/trace_format.h"
#include "util/error.h"
#include "bench_timing.h"

using namespace rtusim;
namespace fs = std::filesystem;

namespace {

using rtusim::bench_timing::median_seconds;

constexpr int kReps = 5;


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
    const TraceReader reader(path);
    const TraceHeader& h = reader.header();
    std::vector<uint64_t> addrs;
    const double decode_s = median_seconds(kReps, [&] { addrs = reader.decode(); });
    const double n = static_cast<double>(addrs.size());
    std::printf("  trace     %s: %zu references, %s, layout %s, %.2f bytes/reference\n",
                path.string().c_str(), addrs.size(), h.format == TraceFormat::kBin ? "bin" : "din",
                h.layout.c_str(), h.format == TraceFormat::kBin ? double(h.payload_bytes) / n : 0.0);

    CacheParams params;  // 8 KB, 4-way, 64 B, lru
    uint64_t misses = 0;
    const double replay_s = median_seconds(kReps, [&] {
      SetAssocCache c(params);
      misses = c.replay(addrs);
    });
    const double both_s = median_seconds(kReps, [&] {
      SetAssocCache c(params);
      g_sink = c.replay(reader.decode());
    });
    std::printf("  %-26s %10.1f Mref/s\n", "decode only (reference)", n / decode_s / 1e6);
    std::printf("  %-26s %10.1f Mref/s   %.2fx decode time; %llu misses (%.3f%%)\n",
                "replay 8K/4-way/64B LRU", n / replay_s / 1e6, replay_s / decode_s,
                static_cast<unsigned long long>(misses), 100.0 * double(misses) / n);
    std::printf("  %-26s %10.1f Mref/s\n", "decode + replay", n / both_s / 1e6);
    rtusim::bench_timing::print_ratio("trace_replay_bench", "decode + 8K/4-way/64B LRU",
                                      "decode + replay", n / both_s / 1e6, "decode only",
                                      n / decode_s / 1e6, "Mref/s");
    if (!tmp.empty()) fs::remove_all(tmp);
    return 0;
  } catch (const InputError& e) {
    std::fprintf(stderr, "trace_replay_bench: %s\n", e.what());
    return 2;
  }
}
