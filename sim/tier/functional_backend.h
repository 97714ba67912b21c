// The functional tier: host traversal with every fetch sent through the behavioural caches
// (node L1, data cache or straight to DRAM), and each ray's DRAM bytes charged to its pixel.
// With one ray in flight each ray is traversed to the end in turn. With more (the interleaved
// mode, functional.rays_in_flight) up to that many rays of a batch are in traversal at once and
// take one traversal step each in turn (round-robin over the slots); a finished ray's slot takes
// the batch's next ray. That is the cycle tier's ray interleaving without time: it predicts the
// node stream of a unit that holds that many rays, at about the functional tier's cost. With
// functional.timed the turns follow a cheap model of the unit's timing instead
// (TimedInterleaver), which also estimates the cycle tier's cycles.
#pragma once
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "cache/fetch_cache.h"
#include "layout/memory_image.h"
#include "tier/timed_interleaver.h"
#include "tracer/trace_backend.h"

namespace rtusim {

class FunctionalBackend final : public TraceBackend {
 public:
  // `timing`: the timed mode's params (the cycle tier's, derived); nullptr: untimed.
  // `timed_segments`, `timed_warmup_rays`: the timed mode's runs (TimedInterleaver).
  FunctionalBackend(const MemoryImage& image, const FetchCacheParams& caches, uint32_t pixels,
                    int rays_in_flight = 1, const CycleParams* timing = nullptr,
                    int timed_segments = 1, int timed_warmup_rays = 256);
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override;
  // Replay (parallel tracing) reproduces one ray at a time only: the interleaved and timed
  // modes stay serial.
  const MemoryImage* replay_image() const override {
    return rays_in_flight_ > 1 || timed_ ? nullptr : &image_;
  }
  void replay(const FetchLog& log) override;
  ReplayNeeds replay_needs() const override;

  const FetchCache& caches() const { return caches_; }
  // DRAM bytes (all streams) caused by each pixel's whole ray tree.
  const std::vector<uint64_t>& pixel_dram_bytes() const { return pixel_dram_bytes_; }
  int rays_in_flight() const { return rays_in_flight_; }
  // The timed mode's model; nullptr when untimed.
  const TimedInterleaver* timed() const { return timed_.get(); }

 private:
  // The interleaved mode's trace (rays_in_flight_ > 1).
  void trace_interleaved(std::span<const RayRecord> rays, std::span<Hit> hits);
  // Charges `bytes` to `pixel`; a ray outside the frame is a tracer bug, not something to drop.
  void charge(uint32_t pixel, uint64_t bytes) {
    if (pixel >= pixel_dram_bytes_.size()) [[unlikely]]
      throw std::logic_error("functional tier: a ray of pixel " + std::to_string(pixel) +
                             " outside the frame's " + std::to_string(pixel_dram_bytes_.size()));
    pixel_dram_bytes_[pixel] += bytes;
  }

  const MemoryImage& image_;
  FetchCache caches_;
  std::vector<uint64_t> pixel_dram_bytes_;
  int rays_in_flight_;
  std::unique_ptr<TimedInterleaver> timed_;
};

}  // namespace rtusim
