// Host traversal of a ray batch.
#include "tracer/host_backend.h"

#include "layout/layout_dispatch.h"
#include "tracer/fetch_log.h"
#include "traversal/traversal.h"

namespace rtusim {

void HostBackend::trace(std::span<const RayRecord> rays, std::span<Hit> hits) {
  with_layout_decoder(image_, [&]<class Decoder>() {
    for (size_t i = 0; i < rays.size(); ++i)
      hits[i] = traverse<Decoder>(image_, rays[i].ray, rays[i].any_hit(), counts_);
  });
}

void HostBackend::replay(const FetchLog& log) {
  struct CountingSink {
    FetchCounts& counts;
    void fetch(Stream s, uint64_t addr, uint32_t bytes) { counts.fetch(s, addr, bytes); }
    void end_ray(uint32_t, RayKind) {}
  } sink{counts_};
  log.replay(sink);
}

}  // namespace rtusim
