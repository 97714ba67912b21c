// The functional tier: host traversal with every fetch sent through the behavioural caches
// (node L1, data cache or straight to DRAM), and each ray's DRAM bytes charged to its pixel.
#pragma once
#include <vector>

#include "cache/stream_caches.h"
#include "layout/memory_image.h"
#include "tracer/ray_batch.h"

namespace rtusim {

class FunctionalBackend final : public TraceBackend {
 public:
  FunctionalBackend(const MemoryImage& image, const FetchCacheParams& caches, uint32_t pixels);
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override;
  const MemoryImage* replay_image() const override { return &image_; }
  void replay(const FetchLog& log) override;

  const FetchCache& caches() const { return caches_; }
  // DRAM bytes (all streams) caused by each pixel's whole ray tree.
  const std::vector<uint64_t>& pixel_dram_bytes() const { return pixel_dram_bytes_; }

 private:
  const MemoryImage& image_;
  FetchCache caches_;
  std::vector<uint64_t> pixel_dram_bytes_;
};

}  // namespace rtusim
