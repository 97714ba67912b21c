// Node-stream recording through the shared traversal step.
#include "trace/node_stream_backend.h"

#include "app/pipeline.h"
#include "layout/layout_dispatch.h"
#include "scene/pinhole_camera.h"
#include "trace/trace_format.h"
#include "tracer/whitted_tracer.h"
#include "traversal/traversal.h"

namespace rtusim {
namespace {

// The traversal sink: node fetches to the recorder, the other streams dropped.
struct NodeOnlySink {
  NodeStreamRecorder& recorder;
  void fetch(Stream s, uint64_t addr, uint32_t /*bytes*/) {
    if (s == Stream::kNode) recorder.node_fetch(addr);
  }
};

struct DigestRecorder final : NodeStreamRecorder {
  TraceDigest digest;
  void node_fetch(uint64_t addr) override { digest.add(addr); }
};

struct WriterRecorder final : NodeStreamRecorder {
  TraceWriter& writer;
  explicit WriterRecorder(TraceWriter& w) : writer(w) {}
  void node_fetch(uint64_t addr) override { writer.append(addr); }
};

void render_frame(const Prepared& p, const MemoryImage& image, NodeStreamRecorder& recorder) {
  const int w = p.config.image.width, h = p.config.image.height;
  const PinholeCamera camera(p.camera, w, h);
  NodeStreamBackend backend(image, recorder);
  WhittedTracer tracer(p.scene, p.config.tracer, backend);
  tracer.render(camera, w, h);
}

}  // namespace

void NodeStreamBackend::trace(std::span<const RayRecord> rays, std::span<Hit> hits) {
  with_layout_decoder(image_, [&]<class Decoder>() {
    NodeOnlySink sink{recorder_};
    for (size_t i = 0; i < rays.size(); ++i)
      hits[i] = traverse<Decoder>(image_, rays[i].ray, rays[i].any_hit(), sink);
  });
}

TraceDigest node_stream_digest(const Prepared& p, const MemoryImage& image) {
  DigestRecorder r;
  render_frame(p, image, r);
  return r.digest;
}

void write_node_stream(const Prepared& p, const MemoryImage& image, TraceWriter& writer) {
  WriterRecorder r(writer);
  render_frame(p, image, r);
}

}  // namespace rtusim
