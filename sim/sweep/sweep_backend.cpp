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
      if (b.node_chunk_.size() == kChunkFetches) b.hand_off();
      return;
    }
    if (bytes != 0) b.bursts_[tag] += FetchCache::dram_bursts(addr, bytes);
    if (b.data_) {
      b.data_chunk_.push_back({addr, bytes, static_cast<uint32_t>(tag)});
      if (b.data_chunk_.size() == kChunkFetches) b.hand_off();
    }
  }
};

SweepBackend::SweepBackend(const MemoryImage& image, CacheSweep& nodes, CacheSweep* data)
    : image_(image), nodes_(nodes), data_(data) {
  node_chunk_.reserve(kChunkFetches);
  node_feeding_.reserve(kChunkFetches);
  if (data_) {
    data_chunk_.reserve(kChunkFetches);
    data_feeding_.reserve(kChunkFetches);
  }
}

SweepBackend::~SweepBackend() {
  if (in_flight_.valid()) in_flight_.wait();
}

void SweepBackend::trace(std::span<const RayRecord> rays, std::span<Hit> hits) {
  Sink sink{*this};
  with_layout_decoder(image_, [&]<class Decoder>() {
    for (size_t i = 0; i < rays.size(); ++i)
      hits[i] = traverse<Decoder>(image_, rays[i].ray, rays[i].any_hit(), sink);
  });
}

void SweepBackend::hand_off() {
  if (in_flight_.valid()) in_flight_.get();
  node_feeding_.swap(node_chunk_);
  data_feeding_.swap(data_chunk_);
  in_flight_ = std::async(std::launch::async, [this] {
    nodes_.feed(node_feeding_);
    node_feeding_.clear();
    if (data_) data_->feed(data_feeding_);
    data_feeding_.clear();
  });
}

void SweepBackend::flush() {
  hand_off();
  in_flight_.get();
}

}  // namespace rtusim
