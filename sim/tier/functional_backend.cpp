// Functional tier: traversal through the cache model.
#include "tier/functional_backend.h"

#include "layout/layout_dispatch.h"
#include "tracer/fetch_log.h"
#include "traversal/traversal.h"

namespace rtusim {

FunctionalBackend::FunctionalBackend(const MemoryImage& image, const FetchCacheParams& caches,
                                     uint32_t pixels)
    : image_(image), caches_(caches), pixel_dram_bytes_(pixels, 0) {}

void FunctionalBackend::trace(std::span<const RayRecord> rays, std::span<Hit> hits) {
  caches_.with_inlined_node_l1([&](auto& sink) {
    with_layout_decoder(image_, [&]<class Decoder>() {
      for (size_t i = 0; i < rays.size(); ++i) {
        const uint64_t before = caches_.dram_bytes_total();
        hits[i] = traverse<Decoder>(image_, rays[i].ray, rays[i].any_hit(), sink);
        if (rays[i].pixel < pixel_dram_bytes_.size())
          pixel_dram_bytes_[rays[i].pixel] += caches_.dram_bytes_total() - before;
      }
    });
  });
}

// The same cache accesses and pixel charges as trace() of the log's rays.
void FunctionalBackend::replay(const FetchLog& log) {
  caches_.with_inlined_node_l1([&](auto& sink) {
    struct ChargingSink {
      std::remove_reference_t<decltype(sink)>& caches;
      FunctionalBackend& backend;
      uint64_t before;  // DRAM bytes when the current ray began
      void fetch(Stream s, uint64_t addr, uint32_t bytes) { caches.fetch(s, addr, bytes); }
      void end_ray(uint32_t pixel, RayKind) {
        const uint64_t now = backend.caches_.dram_bytes_total();
        if (pixel < backend.pixel_dram_bytes_.size()) backend.pixel_dram_bytes_[pixel] += now - before;
        before = now;
      }
    };
    ChargingSink charging{sink, *this, caches_.dram_bytes_total()};
    log.replay(charging);
  });
}

}  // namespace rtusim
