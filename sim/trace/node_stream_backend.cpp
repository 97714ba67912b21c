// Node-stream recording through the shared traversal step.
#include "trace/node_stream_backend.h"

#include "layout/layout_dispatch.h"
#include "tracer/fetch_log.h"
#include "traversal/traversal.h"

namespace rtusim {
namespace {

// The traversal sink: node fetches to the recorder, the other streams dropped.
struct NodeOnlySink {
  NodeStreamRecorder& recorder;
  void fetch(Stream s, uint64_t addr, uint32_t /*bytes*/) {
    if (s == Stream::kNode) recorder.node_fetch(addr);
  }
  void end_ray(uint32_t /*pixel*/, RayKind, uint64_t /*direct_dram_bytes*/) {}
};

}  // namespace

void NodeStreamBackend::trace(std::span<const RayRecord> rays, std::span<Hit> hits) {
  with_layout_decoder(image_, [&]<class Decoder>() {
    NodeOnlySink sink{recorder_};
    for (size_t i = 0; i < rays.size(); ++i)
      hits[i] = traverse<Decoder>(image_, rays[i].ray, rays[i].any_hit(), sink);
  });
}

void NodeStreamBackend::replay(const FetchLog& log) {
  NodeOnlySink sink{recorder_};
  log.replay(sink);
}

}  // namespace rtusim
