// The functional tier's chip: rays dealt to units, traversed through their caches.
#include "tier/chip_functional_backend.h"

#include <vector>

#include "layout/layout_dispatch.h"
#include "tracer/fetch_log.h"
#include "traversal/traversal.h"

namespace rtusim {

ChipFunctionalBackend::ChipFunctionalBackend(const MemoryImage& image,
                                             const FetchCacheParams& caches,
                                             const ChipParams& chip, uint32_t width,
                                             uint32_t pixels)
    : image_(image), chip_(caches, chip, pixels), dealer_(chip, width) {}

void ChipFunctionalBackend::trace(std::span<const RayRecord> rays, std::span<Hit> hits) {
  with_layout_decoder(image_, [&]<class Decoder>() {
    for (size_t i = 0; i < rays.size(); ++i) {
      const uint32_t u = dealer_.next(rays[i].pixel);
      chip_.unit(u).with_inlined_node_l1([&](auto& sink) {
        hits[i] = traverse<Decoder>(image_, rays[i].ray, rays[i].any_hit(), sink);
      });
      chip_.end_ray(u, rays[i].pixel);
    }
  });
  chip_.drain_ready();
}

// The same cache accesses as trace() of the log's rays: a ray's fetches are held until its end
// names its pixel, and so its unit.
void ChipFunctionalBackend::replay(const FetchLog& log) {
  struct Fetch {
    Stream stream;
    uint32_t bytes;
    uint64_t addr;
  };
  struct DealingSink {
    ChipFunctionalBackend& backend;
    std::vector<Fetch> ray;  // the current ray's fetches
    void fetch(Stream s, uint64_t addr, uint32_t bytes) { ray.push_back({s, bytes, addr}); }
    void end_ray(uint32_t pixel, RayKind, uint64_t /*direct_dram_bytes: none, all logged*/) {
      const uint32_t u = backend.dealer_.next(pixel);
      FetchCache& caches = backend.chip_.unit(u);
      const uint64_t line_mask = ~uint64_t{caches.node_l1().params().line_bytes - 1u};
      caches.with_inlined_node_l1([&](auto& sink) {
        // A one-line node fetch by the one-line path (the same counts, as the plain tier's
        // replay does).
        for (const Fetch& f : ray)
          if (f.stream == Stream::kNode && f.bytes != 0 &&
              ((f.addr ^ (f.addr + f.bytes - 1)) & line_mask) == 0)
            sink.fetch_node_line(f.addr);
          else
            sink.fetch(f.stream, f.addr, f.bytes);
      });
      backend.chip_.end_ray(u, pixel);
      ray.clear();
    }
  };
  DealingSink sink{*this, {}};
  log.replay(sink);
  chip_.drain_ready();
}

}  // namespace rtusim
