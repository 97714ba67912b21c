// `rtusim replay`: a node-fetch trace (bin or din) through one set-associative cache, the node
// L1's parameters (l1.*: 8192 B, 4-way, 64 B lines, lru unless --set).
#include <algorithm>
#include <bit>
#include <cstdio>
#include <span>
#include <type_traits>
#include <vector>

#include "app/commands.h"
#include "cache/cache_config.h"
#include "cache/set_assoc_cache.h"
#include "config/config_reader.h"
#include "trace/trace_format.h"

namespace rtusim {

int replay_command(const ReplayOptions& opts) {
  ConfigReader r = ConfigReader::from_string("", "replay --set");
  for (const auto& o : opts.overrides) r.apply_override(o);
  const CacheParams params = read_cache_params(r, "l1");
  r.reject_unknown_keys();

  TraceReader reader(opts.trace);
  const TraceHeader& h = reader.header();

  // Streams the trace a chunk at a time (memory independent of its length). A fetch reads
  // node_bytes at its address (bin) or the line's size field (din with sizes); a plain din line
  // is one line access (as Dinero IV reads it). A fetch that crosses a line boundary is two
  // accesses, as in the functional tier; a chunk without one replays as single-line accesses.
  constexpr size_t kChunkRecords = size_t{1} << 16;
  std::vector<uint64_t> addrs;
  std::vector<uint32_t> sizes;
  addrs.reserve(kChunkRecords);
  SetAssocCache cache(params);
  uint64_t fetches = 0;
  uint64_t repeats = 0;  // single-line accesses to the line accessed just before: hits
  bool sized = false;    // some din line carried a size
  const uint64_t line_mask = params.line_bytes - 1;
  const unsigned line_shift = static_cast<unsigned>(std::countr_zero(params.line_bytes));
  uint64_t last_line = ~uint64_t{0};  // line of the previous single-line access (none yet)
  while (reader.next(addrs, sizes, kChunkRecords)) {
    fetches += addrs.size();
    cache.visit([&](auto& c) {
      if (!sizes.empty()) {
        sized = true;
        for (size_t i = 0; i < addrs.size(); ++i) c.access_range(addrs[i], std::max(sizes[i], 1u));
        last_line = ~uint64_t{0};
        return;
      }
      bool straddles = false;
      if (h.node_bytes > 1)
        for (const uint64_t a : addrs) straddles |= (a & line_mask) + h.node_bytes > params.line_bytes;
      if (straddles) {
        for (const uint64_t a : addrs) c.access_range(a, h.node_bytes);
        last_line = ~uint64_t{0};
        return;
      }
      // An access to the line accessed just before is a hit that changes no replacement state
      // (touching the most recent way again is a no-op for lru, tree-plru, fifo and random), so
      // such repeats are counted here and only the others go through the cache. Policies behind
      // the virtual seam get every access.
      using Cache = std::decay_t<decltype(c)>;
      if constexpr (std::is_same_v<Cache, BasicSetAssocCache<DynamicPolicy>>) {
        c.replay(addrs);
      } else {
        size_t kept = 0;
        for (const uint64_t a : addrs) {
          const uint64_t line = a >> line_shift;
          addrs[kept] = a;
          kept += line != last_line;
          last_line = line;
        }
        repeats += addrs.size() - kept;
        c.replay(std::span<const uint64_t>(addrs.data(), kept));
      }
    });
  }

  const bool bin = h.format == TraceFormat::kBin;
  std::printf("replay %s: %llu node fetches (%s%s%s)\n", opts.trace.c_str(),
              static_cast<unsigned long long>(fetches),
              bin ? "bin, layout " : sized ? "din with sizes" : "din", bin ? h.layout.c_str() : "",
              bin ? (", " + std::to_string(h.node_bytes) + "-byte nodes").c_str() : "");
  std::printf("  l1        %llu B, %u-way, %u B lines, %s\n",
              static_cast<unsigned long long>(params.size_bytes), params.assoc, params.line_bytes,
              params.policy.c_str());
  const uint64_t acc = cache.accesses() + repeats, miss = cache.misses();
  std::printf("  accesses  %llu\n", static_cast<unsigned long long>(acc));
  std::printf("  misses    %llu\n", static_cast<unsigned long long>(miss));
  std::printf("  miss rate %.4f%%\n", acc ? 100.0 * double(miss) / double(acc) : 0.0);
  std::printf("  dram bytes %llu\n", static_cast<unsigned long long>(cache.bytes_from_dram()));
  return 0;
}

}  // namespace rtusim
