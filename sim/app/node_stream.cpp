// The frame traced through NodeStreamBackend into a digest or a trace writer.
#include "app/node_stream.h"

#include "scene/pinhole_camera.h"
#include "trace/node_stream_backend.h"
#include "tracer/whitted_tracer.h"

namespace rtusim {
namespace {

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
