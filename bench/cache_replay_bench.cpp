// Replays a synthetic 20 M-reference node-address trace through the 8 KB / 4-way / 64 B cache,
// for every replacement policy, and prints the median references/s of 5 repetitions, with a
// plain checksum pass over the same trace (no cache) measured in the same run as the reference.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "cache/policy/random_policy.h"
#include "cache/replacement_policy.h"
#include "cache/set_assoc_cache.h"
#include "bench_timing.h"

using namespace rtusim;

namespace {

using rtusim::bench_timing::median_seconds;

constexpr size_t kRefs = 20'000'000;
constexpr int kReps = 5;

// Node fetches: mostly the next node (depth-first layouts put a child after its parent), some
// jumps into the hot top of the tree, some anywhere in a 4 MB node region; 8-byte nodes.
std::vector<uint64_t> make_trace() {
  SplitMix64 rng(20100101);
  std::vector<uint64_t> t(kRefs);
  uint64_t a = 0;
  for (auto& x : t) {
    const uint32_t r = rng.below(100);
    if (r < 70) a = (a + 8) & ((4u << 20) - 1);
    else if (r < 85) a = uint64_t{rng.below(32 * 1024 / 8)} * 8;
    else a = uint64_t{rng.below(4 * 1024 * 1024 / 8)} * 8;
    x = a;
  }
  return t;
}


volatile uint64_t g_sink;  // keeps results alive

}  // namespace

int main() {
  const std::vector<uint64_t> trace = make_trace();
  const double n = static_cast<double>(trace.size());
  std::printf("cache_replay_bench: %zu node references, 4 MB region, 8 KB / 4-way / 64 B, median of %d\n",
              trace.size(), kReps);

  const double raw_s = median_seconds(kReps, [&] {
    uint64_t sum = 0;
    for (const uint64_t a : trace) sum += a;
    g_sink = sum;
  });
  std::printf("  %-10s %8s %14s %14s %14s %8s\n", "policy", "miss%", "loop Mref/s",
              "access Mref/s", "virtual Mref/s", "x raw");
  std::printf("  %-10s %8s %14.1f %14s %14s %8s\n", "(checksum)", "-", n / raw_s / 1e6, "-", "-",
              "1.0");

  bool consistent = true;
  for (const std::string& policy : known_replacement_policies()) {
    CacheParams p;  // 8 KB, 4-way, 64 B
    p.policy = policy;
    uint64_t loop_misses = 0, access_misses = 0, virtual_misses = 0;
    // Policy chosen at run time, dispatched once per replay loop.
    const double loop_s = median_seconds(kReps, [&] {
      SetAssocCache c(p);
      loop_misses = c.replay(trace);
    });
    // Dispatched per access (what a fetch sink does).
    const double access_s = median_seconds(kReps, [&] {
      SetAssocCache c(p);
      uint64_t m = 0;
      for (const uint64_t a : trace) m += c.access(a) ? 0 : 1;
      access_misses = m;
    });
    // The policy called through the virtual ReplacementPolicy seam.
    const double virtual_s = median_seconds(kReps, [&] {
      SetAssocCache c = SetAssocCache::through_virtual_policy(p);
      virtual_misses = c.replay(trace);
    });
    consistent = consistent && loop_misses == access_misses && loop_misses == virtual_misses;
    std::printf("  %-10s %8.3f %14.1f %14.1f %14.1f %8.1f\n", policy.c_str(),
                100.0 * static_cast<double>(loop_misses) / n, n / loop_s / 1e6,
                n / access_s / 1e6, n / virtual_s / 1e6, loop_s / raw_s);
    rtusim::bench_timing::print_ratio("cache_replay_bench", ("8K/4-way/64B " + policy).c_str(),
                                      "replay loop", loop_s, "checksum loop", raw_s, "s");
  }
  std::printf("  x raw = loop replay time / checksum time; miss counts %s across dispatch forms\n",
              consistent ? "agree" : "DISAGREE");
  return consistent ? 0 : 1;
}
