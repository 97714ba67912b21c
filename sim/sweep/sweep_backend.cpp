#include "sweep/sweep_backend.h"

#include "cache/fetch_cache.h"
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
      b.nodes_.record(b.chunk_[0], addr, bytes, static_cast<uint32_t>(tag));
      if (b.chunk_[0].recorded == kChunkFetches) b.hand_off();
      return;
    }
    if (bytes != 0) b.bursts_[tag] += FetchCache::dram_bursts(addr, bytes, b.burst_bytes_);
    if (b.data_) {
      b.data_->record(b.chunk_[1], addr, bytes, static_cast<uint32_t>(tag));
      if (b.chunk_[1].recorded == kChunkFetches) b.hand_off();
    }
  }
};

namespace {

std::vector<CacheSweep*> sweeps(CacheSweep& nodes, CacheSweep* data) {
  if (data) return {&nodes, data};
  return {&nodes};
}

}  // namespace

SweepBackend::SweepBackend(const MemoryImage& image, CacheSweep& nodes, CacheSweep* data,
                           unsigned threads, uint32_t dram_burst_bytes)
    : image_(image), nodes_(nodes), data_(data), pipeline_(sweeps(nodes, data), threads, kChunksHeld),
      chunk_(data ? 2 : 1), burst_bytes_(dram_burst_bytes) {
  reserve();
}

SweepBackend::~SweepBackend() = default;

void SweepBackend::trace(std::span<const RayRecord> rays, std::span<Hit> hits) {
  Sink sink{*this};
  with_layout_decoder(image_, [&]<class Decoder>() {
    for (size_t i = 0; i < rays.size(); ++i)
      hits[i] = traverse<Decoder>(image_, rays[i].ray, rays[i].any_hit(), sink);
  });
}

void SweepBackend::hand_off() {
  pipeline_.push(chunk_);
  reserve();
}

void SweepBackend::reserve() {
  for (size_t i = 0; i < chunk_.size(); ++i) {
    const CacheSweep& sweep = i == 0 ? nodes_ : *data_;
    SweepChunk& c = chunk_[i];
    if (sweep.keeps_fetches()) c.fetches.reserve(kChunkFetches);
    if (sweep.encodes() && c.words.size() < kChunkFetches) c.words.resize(kChunkFetches);
  }
}

void SweepBackend::flush() {
  hand_off();
  pipeline_.finish();
}

}  // namespace rtusim
