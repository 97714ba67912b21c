// Functional tier: traversal through the cache model.
#include "tier/functional_backend.h"

#include "layout/layout_dispatch.h"
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

}  // namespace rtusim
