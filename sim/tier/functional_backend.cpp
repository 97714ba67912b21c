// Functional tier: traversal through the cache model, one ray at a time or interleaved.
#include "tier/functional_backend.h"

#include <algorithm>

#include "layout/layout_dispatch.h"
#include "tracer/fetch_log.h"
#include "traversal/ray_step_log.h"
#include "traversal/traversal.h"

namespace rtusim {

FunctionalBackend::FunctionalBackend(const MemoryImage& image, const FetchCacheParams& caches,
                                     uint32_t pixels, int rays_in_flight,
                                     const CycleParams* timing, int timed_segments,
                                     int timed_warmup_rays)
    : image_(image), caches_(caches), pixel_dram_bytes_(pixels, 0),
      rays_in_flight_(rays_in_flight),
      timed_(timing ? std::make_unique<TimedInterleaver>(image, *timing, rays_in_flight,
                                                         timed_segments, timed_warmup_rays)
                    : nullptr) {}

void FunctionalBackend::trace(std::span<const RayRecord> rays, std::span<Hit> hits) {
  if (timed_)
    return timed_->trace(rays, hits, caches_,
                         [this](uint32_t pixel, uint64_t bytes) { charge(pixel, bytes); });
  if (rays_in_flight_ > 1) return trace_interleaved(rays, hits);
  caches_.with_inlined_node_l1([&](auto& sink) {
    with_layout_decoder(image_, [&]<class Decoder>() {
      for (size_t i = 0; i < rays.size(); ++i) {
        const uint64_t before = caches_.dram_bytes_total();
        hits[i] = traverse<Decoder>(image_, rays[i].ray, rays[i].any_hit(), sink);
        charge(rays[i].pixel, caches_.dram_bytes_total() - before);
      }
    });
  });
}

void FunctionalBackend::trace_interleaved(std::span<const RayRecord> rays, std::span<Hit> hits) {
  // Each ray's traversal is recorded whole when it starts (it does not depend on the order of
  // the cache accesses) and its steps are sent from the record in turns: one ray's traversal in
  // one go runs much faster on the host than steps interleaved with the other rays'.
  struct Slot {
    RayStepLog log;
    const uint64_t* next = nullptr;  // the next step's first word
    const uint64_t* end = nullptr;
    Hit hit;
    size_t ray = 0;
    bool busy = false;
    uint64_t dram_bytes = 0;  // of the current ray, charged when it ends
  };
  std::vector<Slot> slots(std::min<size_t>(rays_in_flight_, rays.size()));
  caches_.with_inlined_node_l1([&](auto& sink) {
    with_layout_decoder(image_, [&]<class Decoder>() {
      size_t next = 0;
      auto start = [&](Slot& slot) {
        slot.busy = next < rays.size();
        if (!slot.busy) return;
        slot.ray = next++;
        slot.dram_bytes = 0;
        slot.log.clear();
        slot.hit = slot.log.template record<Decoder>(image_, rays[slot.ray]);
        const std::span<const uint64_t> words = slot.log.ray(0);
        slot.next = words.data();
        slot.end = slot.next + words.size();
      };
      for (Slot& slot : slots) start(slot);
      size_t busy = slots.size();
      while (busy > 0) {
        for (Slot& slot : slots) {
          if (!slot.busy) continue;
          // One turn: the ray's next step (none for a ray that misses the scene's bounds).
          if (slot.next != slot.end) {
            const uint64_t before = caches_.dram_bytes_total();
            RayStepLog::take_step(slot.next, slot.end, sink);
            slot.dram_bytes += caches_.dram_bytes_total() - before;
            if (slot.next != slot.end) continue;
          }
          hits[slot.ray] = slot.hit;
          charge(rays[slot.ray].pixel, slot.dram_bytes);
          start(slot);
          if (!slot.busy) --busy;
        }
      }
    });
  });
}

// Node fetches that are repeated hits and list and triangle fetches straight to DRAM are
// counted by the recording threads (FetchLog), when the node L1's policy allows the first.
ReplayNeeds FunctionalBackend::replay_needs() const {
  ReplayNeeds needs;
  if (caches_.node_l1().retouch_neutral())
    needs.node_line_bytes = caches_.node_l1().params().line_bytes;
  needs.lists_triangles_direct = caches_.data_cache() == nullptr;
  needs.dram_burst_bytes = caches_.dram_burst_bytes();
  return needs;
}

// The same cache accesses and pixel charges as trace() of the log's rays.
void FunctionalBackend::replay(const FetchLog& log) {
  caches_.with_inlined_node_l1([&](auto& sink) {
    struct ChargingSink {
      std::remove_reference_t<decltype(sink)>& caches;
      FunctionalBackend& backend;
      uint64_t before;     // DRAM bytes when the current ray began
      uint64_t line_mask;  // ~(node L1 line bytes - 1)
      // fetch() of a one-line node fetch by the one-line path (the same counts): the traversal
      // knows a fetch's size where it makes it, the replay does not, and the general path's
      // range loop and stream dispatch per fetch cost about as much as the lookup itself.
      void fetch(Stream s, uint64_t addr, uint32_t bytes) {
        if (s == Stream::kNode && bytes != 0 && ((addr ^ (addr + bytes - 1)) & line_mask) == 0)
            [[likely]]
          caches.fetch_node_line(addr);
        else
          caches.fetch(s, addr, bytes);
      }
      void end_ray(uint32_t pixel, RayKind, uint64_t direct_dram_bytes) {
        const uint64_t now = backend.caches_.dram_bytes_total();
        backend.charge(pixel, now - before + direct_dram_bytes);
        before = now;
      }
    };
    ChargingSink charging{sink, *this, caches_.dram_bytes_total(),
                          ~uint64_t{caches_.node_l1().params().line_bytes - 1u}};
    log.replay(charging);
  });
  caches_.count_node_hits(log.counted_node_hits());
  for (int s = 0; s < FetchCache::kStreams; ++s) {
    const FetchLog::DirectCount& d = log.direct_counts()[s];
    if (d.fetches) caches_.count_dram_bursts(static_cast<Stream>(s), d.fetches, d.bursts);
  }
}

}  // namespace rtusim
