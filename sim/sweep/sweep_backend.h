// The functional tier's traversal with a fan-out memory side: every fetch is recorded into a
// chunk, and each full chunk is fed, on another thread while tracing goes on into the next
// chunk (one chunk in flight, so the order is kept), to the CacheSweep of the node stream (and to the one of
// the list and triangle streams, when a data cache is swept). Nothing else is kept: the stream is
// evaluated as it is produced. Counts the fetches per stream and the DRAM bursts that lists and
// triangles cost without a data cache.
#pragma once
#include <array>
#include <future>
#include <vector>

#include "layout/memory_image.h"
#include "sweep/cache_sweep.h"
#include "tracer/ray_batch.h"

namespace rtusim {

class SweepBackend final : public TraceBackend {
 public:
  // `data` may be null (no data-cache configuration to evaluate).
  SweepBackend(const MemoryImage& image, CacheSweep& nodes, CacheSweep* data);
  ~SweepBackend() override;
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override;
  // Feeds what is left in the chunks and waits for the caches; call once after the frame.
  void flush();

  uint64_t fetches(Stream s) const { return fetches_[static_cast<int>(s)]; }
  // 64-byte DRAM bursts a stream costs when it goes straight to DRAM (FetchCache's rule).
  uint64_t direct_bursts(Stream s) const { return bursts_[static_cast<int>(s)]; }

 private:
  static constexpr size_t kChunkFetches = 1 << 18;
  struct Sink;
  // Waits for the chunk in flight, then sends the filled chunks off to be fed.
  void hand_off();

  const MemoryImage& image_;
  CacheSweep& nodes_;
  CacheSweep* data_;
  std::vector<SweepFetch> node_chunk_, data_chunk_;      // being filled by the traversal
  std::vector<SweepFetch> node_feeding_, data_feeding_;  // being fed to the caches
  std::future<void> in_flight_;
  std::array<uint64_t, 3> fetches_{}, bursts_{};
};

}  // namespace rtusim
