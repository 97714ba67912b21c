// A node-fetch trace (bin or din) streamed through one set-associative cache: what `rtusim
// replay` counts, as a library call so benchmarks time the same path.
#pragma once
#include <cstdint>

#include "cache/cache_params.h"
#include "trace/trace_format.h"

namespace rtusim {

struct TraceReplayCounts {
  uint64_t fetches = 0;     // trace records
  uint64_t accesses = 0;    // line accesses (a fetch crossing a line boundary is two)
  uint64_t misses = 0;
  uint64_t dram_bytes = 0;
  bool sized = false;       // some din line carried a size
};

// Reads `reader` to its end a chunk at a time (memory independent of the trace's length).
TraceReplayCounts replay_trace(TraceReader& reader, const CacheParams& params);

}  // namespace rtusim
