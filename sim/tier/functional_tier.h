// The functional tier: host traversal through the behavioural caches (no time); attributes
// each ray's DRAM bytes to its pixel.
#pragma once
#include "tier/functional_backend.h"
#include "tier/tier.h"

namespace rtusim {

class FunctionalTier final : public TierRun {
 public:
  static constexpr const char* kName = "functional";
  FunctionalTier(const MemoryImage& image, const TierConfig& config)
      : backend_(image, config.caches, config.pixels) {}

  TraceBackend& backend() override { return backend_; }
  // traversal.{node,list,triangle}_fetches and the caches' keys (FetchCache::write_stats).
  void write_stats(Stats& stats) const override;
  // The same keys from the streams' counters (what a cache sweep has for each of its points).
  static void write_stats(const FetchCache::Counters& counters, bool data_cache_on, Stats& stats);
  std::vector<uint64_t> pixel_dram_bytes() const override { return backend_.pixel_dram_bytes(); }

 private:
  FunctionalBackend backend_;
};

}  // namespace rtusim
