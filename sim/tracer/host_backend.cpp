// Host traversal of a ray batch.
#include "tracer/host_backend.h"

#include "layout/layout_dispatch.h"
#include "tracer/fetch_log.h"
#include "traversal/batch_traversal.h"

namespace rtusim {

void HostBackend::trace(std::span<const RayRecord> rays, std::span<Hit> hits) {
  with_layout_decoder(image_,
                      [&]<class Decoder>() { traverse_batch<Decoder>(image_, rays, hits, counts_); });
}

void HostBackend::join(const TraceBackend& copy) {
  const FetchCounts& c = static_cast<const HostBackend&>(copy).counts_;
  for (size_t i = 0; i < c.fetches.size(); ++i) {
    counts_.fetches[i] += c.fetches[i];
    counts_.bytes[i] += c.bytes[i];
  }
}

void HostBackend::replay(const FetchLog& log) {
  struct CountingSink {
    FetchCounts& counts;
    void fetch(Stream s, uint64_t addr, uint32_t bytes) { counts.fetch(s, addr, bytes); }
    void end_ray(uint32_t, RayKind, uint64_t /*direct_dram_bytes*/) {}
  } sink{counts_};
  log.replay(sink);
}

}  // namespace rtusim
