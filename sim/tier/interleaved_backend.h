// The interleaved functional mode: the functional tier's caches with the cycle tier's ray
// interleaving and no time. Up to `rays_in_flight` rays of a batch are in traversal at once and
// take one traversal step each in turn (round-robin over the slots); a finished ray's slot takes
// the batch's next ray. It predicts the node stream of a unit that holds that many rays, at
// about the functional tier's cost. One ray in flight is the functional tier exactly.
#pragma once
#include <vector>

#include "cache/stream_caches.h"
#include "layout/memory_image.h"
#include "tracer/ray_batch.h"

namespace rtusim {

class ConfigReader;

// functional.rays_in_flight: rays the interleaved functional mode holds (1 = the plain tier).
int read_functional_rays_in_flight(ConfigReader& r);

class InterleavedBackend final : public TraceBackend {
 public:
  InterleavedBackend(const MemoryImage& image, const FetchCacheParams& caches, uint32_t pixels,
                     int rays_in_flight);
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override;

  const FetchCache& caches() const { return caches_; }
  // DRAM bytes (all streams) caused by each pixel's whole ray tree.
  const std::vector<uint64_t>& pixel_dram_bytes() const { return pixel_dram_bytes_; }

 private:
  const MemoryImage& image_;
  FetchCache caches_;
  std::vector<uint64_t> pixel_dram_bytes_;
  int rays_in_flight_;
};

}  // namespace rtusim
