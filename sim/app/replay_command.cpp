// `rtusim replay`: a node-fetch trace (bin or din) through one set-associative cache, the node
// L1's parameters (l1.*: 8192 B, 4-way, 64 B lines, lru unless --set).
#include <cstdio>

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

  const TraceReader reader(opts.trace);
  const std::vector<uint64_t> addrs = reader.decode();
  const TraceHeader& h = reader.header();

  // A fetch reads node_bytes at its address (bin); a din trace gives addresses only, one line
  // access each (as Dinero IV reads it). A fetch that crosses a line boundary is two accesses,
  // as in the functional tier.
  bool straddles = false;
  if (h.node_bytes > 1)
    for (const uint64_t a : addrs)
      straddles |= (a % params.line_bytes) + h.node_bytes > params.line_bytes;
  SetAssocCache cache(params);
  if (straddles)
    for (const uint64_t a : addrs) cache.access_range(a, h.node_bytes);
  else
    cache.replay(addrs);

  const bool bin = h.format == TraceFormat::kBin;
  std::printf("replay %s: %zu node fetches (%s%s%s)\n", opts.trace.c_str(), addrs.size(),
              bin ? "bin, layout " : "din", bin ? h.layout.c_str() : "",
              bin ? (", " + std::to_string(h.node_bytes) + "-byte nodes").c_str() : "");
  std::printf("  l1        %llu B, %u-way, %u B lines, %s\n",
              static_cast<unsigned long long>(params.size_bytes), params.assoc, params.line_bytes,
              params.policy.c_str());
  const uint64_t acc = cache.accesses(), miss = cache.misses();
  std::printf("  accesses  %llu\n", static_cast<unsigned long long>(acc));
  std::printf("  misses    %llu\n", static_cast<unsigned long long>(miss));
  std::printf("  miss rate %.4f%%\n", acc ? 100.0 * double(miss) / double(acc) : 0.0);
  std::printf("  dram bytes %llu\n", static_cast<unsigned long long>(cache.bytes_from_dram()));
  return 0;
}

}  // namespace rtusim
