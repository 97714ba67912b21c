// The functional tier's traversal with a fan-out memory side: every fetch is recorded into a
// chunk, and each full chunk goes to a SweepPipeline that feeds it, on worker threads while
// tracing goes on into the next chunks, to the CacheSweep of the node stream (and to the one of
// the list and triangle streams, when a data cache is swept). Only a few chunks are held: the
// stream is evaluated as it is produced. Counts the fetches per stream and the DRAM bursts that lists and
// triangles cost without a data cache.
#pragma once
#include <array>
#include <vector>

#include "layout/memory_image.h"
#include "sweep/cache_sweep.h"
#include "sweep/sweep_pipeline.h"
#include "tracer/trace_backend.h"

namespace rtusim {

class SweepBackend final : public TraceBackend {
 public:
  // `data` may be null (no data-cache configuration to evaluate); `threads` feed the caches.
  // `dram_burst_bytes`: the bursts lists and triangles cost straight from DRAM.
  SweepBackend(const MemoryImage& image, CacheSweep& nodes, CacheSweep* data, unsigned threads,
               uint32_t dram_burst_bytes);
  ~SweepBackend() override;
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override;
  // Feeds what is left in the chunks and waits for the caches; call once after the frame.
  void flush();

  uint64_t fetches(Stream s) const { return fetches_[static_cast<int>(s)]; }
  // DRAM bursts a stream costs when it goes straight to DRAM (FetchCache's rule).
  uint64_t direct_bursts(Stream s) const { return bursts_[static_cast<int>(s)]; }
  uint32_t dram_burst_bytes() const { return burst_bytes_; }

 private:
  static constexpr size_t kChunkFetches = 1 << 16;
  static constexpr size_t kChunksHeld = 16;
  struct Sink;
  // Sends the filled chunk off to be fed.
  void hand_off();
  void reserve();  // room in the chunk being filled for a chunk's fetches

  const MemoryImage& image_;
  CacheSweep& nodes_;
  CacheSweep* data_;
  SweepPipeline pipeline_;
  SweepPipeline::Lists chunk_;  // being filled by the traversal: nodes, then lists and triangles
  uint32_t burst_bytes_;
  std::array<uint64_t, 3> fetches_{}, bursts_{};
};

}  // namespace rtusim
