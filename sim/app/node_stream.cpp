// The frame traced through NodeStreamBackend into a digest or a trace writer.
#include "app/node_stream.h"

#include "chip/ray_dealer.h"
#include "scene/pinhole_camera.h"
#include "tier/chip_functional_backend.h"
#include "trace/node_stream_backend.h"
#include "tracer/parallel_render.h"

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
  const std::vector<uint32_t> order = chip_pixel_order(p.config.chip, w, h);
  parallel_render(p.scene, p.config.tracer, backend, camera, w, h, order);
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

void write_l2_stream(const Prepared& p, const MemoryImage& image, TraceWriter& writer) {
  const int w = p.config.image.width, h = p.config.image.height;
  ChipFunctionalBackend backend(image, p.config.fetch_caches(), p.config.chip,
                                static_cast<uint32_t>(w), static_cast<uint32_t>(w * h));
  backend.chip().observe_l2([&](const NextLevelRequest& r, uint32_t) { writer.append(r.addr); });
  const std::vector<uint32_t> order = chip_pixel_order(p.config.chip, w, h);
  parallel_render(p.scene, p.config.tracer, backend, PinholeCamera(p.camera, w, h), w, h, order);
  backend.end_frame();
}

}  // namespace rtusim
