// The chip's memory in the functional tier: each unit's private caches (a FetchCache: node L1,
// data cache or straight past it) and, when l2.enable, the L2 they share in front of DRAM.
//
// The units run free, in no time. The L2 takes their requests (missed lines, bursts that go past
// a unit's caches) in one fixed order: as if the units took turns one fetch at a time from the
// start of the frame. A request's turn is its ordinal, its unit's fetch count when it was made;
// the lowest ordinal goes first, ties to the lower unit. The order depends only on each unit's
// own fetch stream, not on how rays reach the units (batches, chunks, threads), so every result
// is the same for any thread count.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "cache/fetch_cache.h"
#include "cache/set_assoc_cache.h"
#include "chip/chip_params.h"

namespace rtusim {

// Hit, miss and byte counts at the L2, of one stream or one initiator.
struct L2Counters {
  uint64_t accesses = 0, hits = 0, misses = 0;
  uint64_t bytes_in = 0;    // requested by the units (lines and bursts)
  uint64_t dram_bytes = 0;  // read from DRAM for its misses
};

// The L2's counts per stream and per unit (what the chip's l2.* and units.<i>.l2.* keys say).
struct ChipL2Counts {
  std::array<L2Counters, 3> streams{};  // by Stream
  std::vector<L2Counters> units;
};

class ChipCaches {
 public:
  // `pixels`: the frame's, for the DRAM bytes charged to each. Throws InputError on bad params.
  ChipCaches(const FetchCacheParams& unit_caches, const ChipParams& chip, uint32_t pixels);
  ChipCaches(const ChipCaches&) = delete;  // the units' caches log into their own vectors
  ChipCaches& operator=(const ChipCaches&) = delete;

  uint32_t units() const { return static_cast<uint32_t>(units_.size()); }
  // Unit `u`'s private caches: traverse its rays through them.
  FetchCache& unit(uint32_t u) { return units_[u].caches; }
  const FetchCache& unit(uint32_t u) const { return units_[u].caches; }
  bool has_l2() const { return l2_cache_.has_value(); }

  // Ends a ray that unit `u` traced: what it caused is charged to `pixel` (its DRAM bytes, with
  // an L2 when the L2 takes its requests).
  void end_ray(uint32_t u, uint32_t pixel);
  // Sends the L2 every request that no request still to come can precede (with an L2).
  void drain_ready() { drain(false); }
  // Sends the L2 every request: the frame is over.
  void drain_all() { drain(true); }

  // Calls f(request, unit) for each request the L2 takes, in its order (`rtusim trace --level
  // l2`, the L2 sweep).
  using L2Observer = std::function<void(const NextLevelRequest&, uint32_t)>;
  void observe_l2(L2Observer f) { l2_observer_ = std::move(f); }

  uint64_t rays(uint32_t u) const { return units_[u].rays; }
  // The L2's counts per stream (dram_bytes: what it read from DRAM) and per unit.
  const ChipL2Counts& l2_counts() const { return l2_; }
  const std::array<L2Counters, FetchCache::kStreams>& l2_streams() const { return l2_.streams; }
  const L2Counters& l2_unit(uint32_t u) const { return l2_.units[u]; }
  const SetAssocCache* l2() const { return l2_cache_ ? &*l2_cache_ : nullptr; }
  // The units' counters, stream by stream, added up.
  FetchCache::Counters total_counters() const;
  // DRAM bytes (all streams) caused by each pixel's rays.
  const std::vector<uint64_t>& pixel_dram_bytes() const { return pixel_dram_bytes_; }

 private:
  struct Unit {
    FetchCache caches;
    std::vector<NextLevelRequest> pending;  // to the L2, from `head` on
    size_t head = 0;
    size_t ray_first = 0;        // pending index of the current ray's first request
    uint64_t ray_dram_from = 0;  // without an L2: DRAM bytes when the current ray began
    uint64_t rays = 0;
  };
  void drain(bool all);
  void charge(uint32_t pixel, uint64_t bytes);

  std::vector<Unit> units_;
  std::optional<SetAssocCache> l2_cache_;
  ChipL2Counts l2_;
  std::vector<uint64_t> pixel_dram_bytes_;
  L2Observer l2_observer_;
};

}  // namespace rtusim
