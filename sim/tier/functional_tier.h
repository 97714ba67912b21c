// The functional tier: host traversal through the behavioural caches (no time); attributes
// each ray's DRAM bytes to its pixel. functional.rays_in_flight > 1 interleaves the rays'
// traversal steps (FunctionalBackend).
// On a chip of several units or with an L2 the rays go through ChipFunctionalBackend instead.
#pragma once
#include <memory>

#include "tier/chip_functional_backend.h"
#include "tier/functional_backend.h"
#include "tier/tier.h"

namespace rtusim {

class FunctionalTier final : public TierRun {
 public:
  static constexpr const char* kName = "functional";
  static constexpr const char* kSummary = "caches, no time";
  // Runs share nothing but the (read-only) scene and image: layouts may run on other threads.
  static constexpr LayoutConcurrency kLayoutConcurrency = LayoutConcurrency::kThreads;
  FunctionalTier(const MemoryImage& image, const TierConfig& config);

  TraceBackend& backend() override {
    return chip_ ? static_cast<TraceBackend&>(*chip_) : *backend_;
  }
  void end_frame() override {
    if (chip_) chip_->end_frame();
  }
  // traversal.{node,list,triangle}_fetches, the caches' keys (FetchCache::write_stats) and, in
  // the interleaved and timed modes, functional.rays_in_flight; in the timed mode
  // functional.timed and the estimate.* keys (TimedInterleaver::write_stats). On a chip the
  // same keys are the units' sums, units.<i>.* each unit's, and l2.* the L2's (dram.bytes.*
  // then what the L2 read).
  void write_stats(Stats& stats) const override;
  // The same keys from the streams' counters (what a cache sweep has for each of its points).
  static void write_stats(const FetchCache::Counters& counters, bool data_cache_on, Stats& stats);
  // The same keys on a chip, its L2's counts `l2` (the chip's own, or a sweep's for another L2
  // over the same requests).
  static void write_chip_stats(const ChipCaches& chip, const ChipL2Counts& l2, Stats& stats);
  std::vector<uint64_t> pixel_dram_bytes() const override {
    return chip_ ? chip_->chip().pixel_dram_bytes() : backend_->pixel_dram_bytes();
  }

 private:
  std::unique_ptr<FunctionalBackend> backend_;   // one unit, no L2
  std::unique_ptr<ChipFunctionalBackend> chip_;  // else
};

}  // namespace rtusim
