// Host traversal of a ray batch for its hits.
#include "tracer/hit_backend.h"

#include "layout/layout_dispatch.h"
#include "traversal/batch_traversal.h"

namespace rtusim {

void HitBackend::trace(std::span<const RayRecord> rays, std::span<Hit> hits) {
  NullFetchSink none;
  with_layout_decoder(image_,
                      [&]<class Decoder>() { traverse_batch<Decoder>(image_, rays, hits, none); });
}

}  // namespace rtusim
