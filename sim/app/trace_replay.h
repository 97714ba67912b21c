// A node-fetch trace (bin or din) streamed through one set-associative cache: what `rtusim
// replay` counts, as a library call so benchmarks time the same path.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>

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

// Moves the addresses whose line (address >> line_shift) differs from the line before them
// (`last_line` before the first) to the front, in order, and returns how many; `last_line` ends
// as the last address's line. replay_trace's filter of repeated single-line accesses.
size_t drop_repeated_lines(std::span<uint64_t> addrs, unsigned line_shift, uint64_t& last_line);

// Records per chunk replay_trace() reads (32 KB of addresses: they stay in the core's L2).
constexpr size_t kReplayChunkRecords = size_t{1} << 12;

// Reads `reader` to its end a chunk at a time, kReplayChunkRecords each (memory independent of
// the trace's length).
TraceReplayCounts replay_trace(TraceReader& reader, const CacheParams& params);

}  // namespace rtusim
