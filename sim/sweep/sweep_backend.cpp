#include "sweep/sweep_backend.h"

#include "cache/stream_caches.h"
#include "layout/layout_dispatch.h"
#include "traversal/traversal.h"

namespace rtusim {

// The traversal sink: records each fetch into its chunk, feeding full chunks on.
struct SweepBackend::Sink {
  SweepBackend& b;
  void fetch(Stream s, uint64_t addr, uint32_t bytes) {
    const int tag = static_cast<int>(s);
    ++b.fetches_[tag];
    if (s == Stream::kNode) {
      b.node_chunk_.push_back({addr, bytes, static_cast<uint32_t>(tag)});
      if (b.node_chunk_.size() == kChunkFetches) b.flush();
      return;
    }
    if (bytes != 0) b.bursts_[tag] += FetchCache::dram_bursts(addr, bytes);
    if (b.data_) {
      b.data_chunk_.push_back({addr, bytes, static_cast<uint32_t>(tag)});
      if (b.data_chunk_.size() == kChunkFetches) b.flush();
    }
  }
};

SweepBackend::SweepBackend(const MemoryImage& image, CacheSweep& nodes, CacheSweep* data)
    : image_(image), nodes_(nodes), data_(data) {
  node_chunk_.reserve(kChunkFetches);
  if (data_) data_chunk_.reserve(kChunkFetches);
}

void SweepBackend::trace(std::span<const RayRecord> rays, std::span<Hit> hits) {
  Sink sink{*this};
  with_layout_decoder(image_, [&]<class Decoder>() {
    for (size_t i = 0; i < rays.size(); ++i)
      hits[i] = traverse<Decoder>(image_, rays[i].ray, rays[i].any_hit(), sink);
  });
}

void SweepBackend::flush() {
  nodes_.feed(node_chunk_);
  node_chunk_.clear();
  if (data_) {
    data_->feed(data_chunk_);
    data_chunk_.clear();
  }
}

}  // namespace rtusim
