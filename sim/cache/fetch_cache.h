// The memory side of the functional tier: a fetch sink for traversal_step() that sends the node
// stream through the node L1 and the list and triangle streams through a second cache (the
// "data cache", shared by both) or, when that is off, straight to DRAM.
//
// Accounting, per stream (Stream::kNode, kList, kTriangle):
//  - fetches: fetch() calls; accesses: line accesses (a fetch touching two lines is two);
//  - hits / misses: of those accesses;
//  - dram_bytes: misses x line_bytes of the cache the stream goes through. A stream that goes
//    straight to DRAM is read in whole DRAM bursts of dram_burst_bytes (dram.bus_bytes x
//    dram.burst_length, 64 by default, as the cycle tier reads them): each fetch costs the
//    aligned bursts its bytes touch (a 36-byte triangle is 64 or 128 bytes), and each burst
//    counts as one access and one miss.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cache/cache_params.h"
#include "cache/set_assoc_cache.h"
#include "layout/memory_image.h"

namespace rtusim {

class Stats;

struct FetchCacheParams {
  CacheParams node_l1;                    // the node L1 (config keys l1.*)
  std::optional<CacheParams> data_cache;  // lists + triangles; nullopt = straight to DRAM
  uint32_t dram_burst_bytes = 64;         // a DRAM burst: dram.bus_bytes x dram.burst_length
};

struct StreamCounters {
  uint64_t fetches = 0;
  uint64_t accesses = 0;
  uint64_t hits = 0;
  uint64_t misses = 0;
  uint64_t dram_bytes = 0;

  // Field by field: what counters grew by between two readings, and sums of such growths.
  StreamCounters& operator+=(const StreamCounters& o) {
    fetches += o.fetches;
    accesses += o.accesses;
    hits += o.hits;
    misses += o.misses;
    dram_bytes += o.dram_bytes;
    return *this;
  }
  StreamCounters operator-(const StreamCounters& o) const {
    return {fetches - o.fetches, accesses - o.accesses, hits - o.hits, misses - o.misses,
            dram_bytes - o.dram_bytes};
  }
};

// A request that a unit's private caches send to the next level (the chip's shared L2): a missed
// line of a cache, or a DRAM burst of a stream that goes straight past them.
struct NextLevelRequest {
  uint64_t ordinal;  // the unit's fetches so far, this one's included: the chip's turn order
  uint64_t addr;     // first byte, aligned to `bytes`
  uint32_t bytes;    // the line or the burst
  uint32_t pixel;    // of the ray that made it (set by the chip when the ray ends)
  Stream stream;
};

class FetchCache {
 public:
  static constexpr int kStreams = 3;

  using Counters = std::array<StreamCounters, kStreams>;

  // The DRAM bursts of `burst_bytes` that `bytes` (> 0) at `addr` touch.
  static uint64_t dram_bursts(uint64_t addr, uint32_t bytes, uint32_t burst_bytes) {
    return (addr + bytes - 1) / burst_bytes - addr / burst_bytes + 1;
  }
  uint32_t dram_burst_bytes() const { return burst_bytes_; }

  // Throws InputError on bad params (keys named "l1.*" and "dcache.*").
  explicit FetchCache(const FetchCacheParams& p);

  // The traversal sink call: `bytes` read at `addr` on stream `s`; returns the DRAM bytes it
  // caused.
  uint64_t fetch(Stream s, uint64_t addr, uint32_t bytes) {
    StreamCounters& c = counters_[static_cast<int>(s)];
    ++c.fetches;
    if (bytes == 0) return 0;
    if (s == Stream::kNode) return count(s, c, node_l1_, addr, bytes);
    if (data_cache_) return count(s, c, *data_cache_, addr, bytes);
    return count_to_dram(s, c, addr, bytes);
  }
  // fetch() of `bytes` (> 0) on a list or triangle stream when there is no data cache
  // (data_cache() is nullptr): straight to DRAM, in its bursts.
  uint64_t fetch_to_dram(Stream s, uint64_t addr, uint32_t bytes) {
    StreamCounters& c = counters_[static_cast<int>(s)];
    ++c.fetches;
    return count_to_dram(s, c, addr, bytes);
  }

  // Counts what a replay log counted instead of logging (tracer/fetch_log.h): `n` node fetches
  // that were one-line hits; `fetches` on list or triangle stream `s` straight to DRAM in
  // `bursts` bursts.
  void count_node_hits(uint64_t n) {
    StreamCounters& c = counters_[static_cast<int>(Stream::kNode)];
    c.fetches += n;
    c.accesses += n;
    c.hits += n;
  }
  void count_dram_bursts(Stream s, uint64_t fetches, uint64_t bursts) {
    StreamCounters& c = counters_[static_cast<int>(s)];
    c.fetches += fetches;
    add_dram_bursts(c, bursts);
  }

  // Calls f(sink) with a sink equivalent to this FetchCache whose node stream goes to the
  // concrete node-L1 type, so a traversal loop over `sink` inlines the L1 lookup: the policy is
  // dispatched once per call instead of once per fetch.
  template <class F>
  void with_inlined_node_l1(F&& f) {
    node_l1_.visit([&](auto& l1) {
      InlinedSink<std::remove_reference_t<decltype(l1)>> sink{*this, l1};
      f(sink);
    });
  }

  // A miss of stream `s` that the timed mode found merged into a read of its line already
  // outstanding (the tags had lost the line while its MSHR was busy): counted as a miss, as the
  // unit's L1 counts it, but DRAM reads the line once, so its `bytes` are not DRAM's.
  void refund_merged_miss(Stream s, uint64_t bytes) {
    counters_[static_cast<int>(s)].dram_bytes -= bytes;
  }

  // From now on every request to the next level (each counted in dram_bytes) is also appended
  // to `log` (nullptr: none). The log outlives the cache or is reset before it ends.
  void log_next_level(std::vector<NextLevelRequest>* log) { log_ = log; }
  // Fetches so far, all streams.
  uint64_t fetches() const {
    return counters_[0].fetches + counters_[1].fetches + counters_[2].fetches;
  }

  const StreamCounters& stream(Stream s) const { return counters_[static_cast<int>(s)]; }
  uint64_t dram_bytes_total() const { return dram_bytes_total(counters_); }
  static uint64_t dram_bytes_total(const Counters& c) {
    return c[0].dram_bytes + c[1].dram_bytes + c[2].dram_bytes;
  }
  const SetAssocCache& node_l1() const { return node_l1_; }
  const SetAssocCache* data_cache() const { return data_cache_ ? &*data_cache_ : nullptr; }

  // Writes l1.{accesses,hits,misses}, dcache.{accesses,hits,misses} (when on),
  // fetch.{nodes,lists,triangles}.{fetches,accesses,hits,misses} and
  // dram.bytes.{nodes,lists,triangles,total}.
  void write_stats(Stats& stats) const { write_stats(counters_, data_cache_.has_value(), stats); }
  // The same keys from per-stream counters (the node L1 is the node stream's cache; the data
  // cache, when on, the list and triangle streams').
  static void write_stats(const Counters& counters, bool data_cache_on, Stats& stats);
  const Counters& counters() const { return counters_; }
  // Takes the lines (tags and replacement state) of `other`, a cache of the same params, and
  // `counters` as its counters: a copy that went on elsewhere hands its state back.
  void take_lines(const FetchCache& other, const Counters& counters) {
    burst_bytes_ = other.burst_bytes_;
    node_l1_ = other.node_l1_;
    data_cache_ = other.data_cache_;
    counters_ = counters;
  }

 private:
  template <class Concrete>
  struct InlinedSink {
    FetchCache& caches;
    Concrete& node_l1;
    uint64_t fetch(Stream s, uint64_t addr, uint32_t bytes) {
      if (s != Stream::kNode) return caches.fetch(s, addr, bytes);
      StreamCounters& c = caches.counters_[static_cast<int>(Stream::kNode)];
      ++c.fetches;
      return bytes != 0 ? caches.count_in(Stream::kNode, c, node_l1, addr, bytes) : 0;
    }
    uint64_t fetch_to_dram(Stream s, uint64_t addr, uint32_t bytes) {
      return caches.fetch_to_dram(s, addr, bytes);
    }
    // fetch(Stream::kNode, addr, bytes) of a fetch whose bytes (> 0) lie in one line of the
    // node L1, with one line access: 0 on a hit, else the line's bytes.
    uint64_t fetch_node_line(uint64_t addr) {
      StreamCounters& c = caches.counters_[static_cast<int>(Stream::kNode)];
      ++c.fetches;
      ++c.accesses;
      if (node_l1.access(addr)) {
        ++c.hits;
        return 0;
      }
      ++c.misses;
      const uint32_t line_bytes = node_l1.params().line_bytes;
      c.dram_bytes += line_bytes;
      if (caches.log_) [[unlikely]]
        caches.log_request(Stream::kNode, addr & ~uint64_t{line_bytes - 1}, line_bytes);
      return line_bytes;
    }
  };

  // Counts `bursts` DRAM bursts read straight from DRAM (each an access and a miss).
  void add_dram_bursts(StreamCounters& c, uint64_t bursts) const {
    c.accesses += bursts;
    c.misses += bursts;
    c.dram_bytes += bursts * burst_bytes_;
  }
  // Counts one fetch of `bytes` (> 0) at `addr` on stream `s` (counters `c`) read straight
  // from DRAM; returns its DRAM bytes.
  uint64_t count_to_dram(Stream s, StreamCounters& c, uint64_t addr, uint32_t bytes) {
    const uint64_t bursts = dram_bursts(addr, bytes, burst_bytes_);
    add_dram_bursts(c, bursts);
    if (log_) [[unlikely]] {
      const uint64_t first = addr / burst_bytes_ * burst_bytes_;
      for (uint64_t b = 0; b < bursts; ++b) log_request(s, first + b * burst_bytes_, burst_bytes_);
    }
    return bursts * burst_bytes_;
  }

  // Counts one fetch of `bytes` at `addr` on stream `s` (counters `c`) through a concrete
  // cache; returns its DRAM bytes.
  template <class Concrete>
  uint64_t count_in(Stream s, StreamCounters& c, Concrete& cache, uint64_t addr, uint32_t bytes) {
    const uint32_t line_bytes = cache.params().line_bytes;
    uint64_t accessed;
    uint32_t missed = 0;
    if (log_) [[unlikely]] {
      // Line by line, as access_range() does, to name the lines missed.
      const uint64_t first = addr / line_bytes, last = (addr + bytes - 1) / line_bytes;
      for (uint64_t line = first; line <= last; ++line)
        if (!cache.access(line * line_bytes)) {
          ++missed;
          log_request(s, line * line_bytes, line_bytes);
        }
      accessed = last - first + 1;
    } else {
      const uint64_t accesses_before = cache.accesses();
      missed = cache.access_range(addr, bytes);
      accessed = cache.accesses() - accesses_before;
    }
    c.accesses += accessed;
    c.hits += accessed - missed;
    c.misses += missed;
    c.dram_bytes += uint64_t{missed} * line_bytes;
    return uint64_t{missed} * line_bytes;
  }

  uint64_t count(Stream s, StreamCounters& c, SetAssocCache& cache, uint64_t addr,
                 uint32_t bytes) {
    // One dispatch.
    return cache.visit([&](auto& concrete) { return count_in(s, c, concrete, addr, bytes); });
  }

  void log_request(Stream s, uint64_t addr, uint32_t bytes) {
    log_->push_back({fetches(), addr, bytes, 0, s});
  }

  SetAssocCache node_l1_;
  std::optional<SetAssocCache> data_cache_;
  uint32_t burst_bytes_ = FetchCacheParams{}.dram_burst_bytes;  // set from the params
  Counters counters_{};
  std::vector<NextLevelRequest>* log_ = nullptr;  // log_next_level()
};

// Stats key stem of a stream: "nodes", "lists", "triangles".
const char* stream_stats_name(Stream s);

}  // namespace rtusim
