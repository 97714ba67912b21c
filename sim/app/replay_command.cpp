// `rtusim replay`: a node-fetch trace (bin or din) through one set-associative cache, the node
// L1's parameters (l1.*: 8192 B, 4-way, 64 B lines, lru unless --set).
#include <cstdio>
#include <string>

#include "app/commands.h"
#include "app/trace_replay.h"
#include "config/config_reader.h"
#include "mem/l1_params.h"
#include "trace/trace_format.h"

namespace rtusim {

int replay_command(const ReplayOptions& opts) {
  ConfigReader r = ConfigReader::from_string("", "replay --set");
  for (const auto& o : opts.overrides) r.apply_override(o);
  const CacheParams params = read_node_l1_geometry(r);
  r.reject_unknown_keys("replay takes l1.size, l1.assoc, l1.line, l1.policy and l1.seed");

  TraceReader reader(opts.trace);
  const TraceHeader& h = reader.header();

  const TraceReplayCounts n = replay_trace(reader, params);

  const bool bin = h.format == TraceFormat::kBin;
  std::printf("replay %s: %llu node fetches (%s%s%s)\n", opts.trace.c_str(),
              static_cast<unsigned long long>(n.fetches),
              bin ? "bin, layout " : n.sized ? "din with sizes" : "din", bin ? h.layout.c_str() : "",
              bin ? (", " + std::to_string(h.node_bytes) + "-byte nodes").c_str() : "");
  std::printf("  l1        %llu B, %u-way, %u B lines, %s\n",
              static_cast<unsigned long long>(params.size_bytes), params.assoc, params.line_bytes,
              params.policy.c_str());
  const uint64_t acc = n.accesses, miss = n.misses;
  std::printf("  accesses  %llu\n", static_cast<unsigned long long>(acc));
  std::printf("  misses    %llu\n", static_cast<unsigned long long>(miss));
  std::printf("  miss rate %.4f%%\n", acc ? 100.0 * double(miss) / double(acc) : 0.0);
  std::printf("  dram bytes %llu\n", static_cast<unsigned long long>(n.dram_bytes));
  return 0;
}

}  // namespace rtusim
