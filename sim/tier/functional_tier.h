// The functional tier: host traversal through the behavioural caches (no time); attributes
// each ray's DRAM bytes to its pixel. functional.rays_in_flight > 1 interleaves the rays'
// traversal steps (FunctionalBackend).
#pragma once
#include "tier/functional_backend.h"
#include "tier/tier.h"

namespace rtusim {

class FunctionalTier final : public TierRun {
 public:
  static constexpr const char* kName = "functional";
  static constexpr const char* kSummary = "caches, no time";
  // Runs share nothing but the (read-only) scene and image: layouts may run on other threads.
  static constexpr LayoutConcurrency kLayoutConcurrency = LayoutConcurrency::kThreads;
  FunctionalTier(const MemoryImage& image, const TierConfig& config)
      : backend_(image, config.caches, config.pixels, config.functional.rays_in_flight,
                 config.functional.timed ? &config.cycle : nullptr,
                 config.functional.timed_segments, config.functional.timed_warmup_rays) {}

  TraceBackend& backend() override { return backend_; }
  // traversal.{node,list,triangle}_fetches, the caches' keys (FetchCache::write_stats) and, in
  // the interleaved and timed modes, functional.rays_in_flight; in the timed mode
  // functional.timed and the estimate.* keys (TimedInterleaver::write_stats).
  void write_stats(Stats& stats) const override;
  // The same keys from the streams' counters (what a cache sweep has for each of its points).
  static void write_stats(const FetchCache::Counters& counters, bool data_cache_on, Stats& stats);
  std::vector<uint64_t> pixel_dram_bytes() const override { return backend_.pixel_dram_bytes(); }

 private:
  FunctionalBackend backend_;
};

}  // namespace rtusim
