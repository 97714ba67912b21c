// Parallel tracing with replay in the single-thread order (see parallel_render.h).
#include "tracer/parallel_render.h"

#include <algorithm>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <vector>

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_for.h>

#include "layout/layout_dispatch.h"
#include "tracer/chunk_pipeline.h"
#include "tracer/fetch_log.h"
#include "traversal/traversal.h"

namespace rtusim {

void TraceBackend::replay(const FetchLog& /*log*/) {
  throw std::logic_error("replay() on a backend without replay_image()");
}

namespace {

constexpr size_t kPixelsPerChunk = 16;  // recursive order: pixels (whole ray trees) per task

// A backend that traverses with the shared step and records the fetches in a log.
class RecordingBackend final : public TraceBackend {
 public:
  RecordingBackend(const MemoryImage& image, FetchLog* log) : image_(image), log_(log) {}
  void set_log(FetchLog* log) { log_ = log; }
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override {
    with_layout_decoder(image_, [&]<class Decoder>() {
      for (size_t i = 0; i < rays.size(); ++i) {
        hits[i] = traverse<Decoder>(image_, rays[i].ray, rays[i].any_hit(), *log_);
        log_->end_ray(rays[i]);
      }
    });
  }

 private:
  const MemoryImage& image_;
  FetchLog* log_;
};

// Recursive order: chunks of pixels with their whole ray trees on the workers.
void render_recursive_parallel(const Scene& scene, const TracerParams& params,
                               TraceBackend& backend, const PinholeCamera& camera,
                               std::span<const uint32_t> pixels, FrameResult& out) {
  const MemoryImage& image = *backend.replay_image();
  struct Slot {
    FetchLog log;
    std::vector<glm::vec3> radiance;  // of the chunk's pixels
    std::array<uint64_t, kRayKinds> rays_by_kind{};
  };
  // Each thread's tracer (made once: its constructor scans the scene) recording into the
  // current chunk's log, and its frame, where render_pixels() puts a pixel's radiance.
  struct Worker {
    RecordingBackend recorder;
    WhittedTracer tracer;
    FrameResult frame;
    Worker(const Scene& scene, const TracerParams& params, const MemoryImage& image,
           const PinholeCamera& camera, const FrameResult& out)
        : recorder(image, nullptr), tracer(scene, params, recorder),
          frame(tracer.begin_frame(camera, out.width, out.height)) {}
  };
  tbb::enumerable_thread_specific<std::unique_ptr<Worker>> workers;
  const size_t chunks = (pixels.size() + kPixelsPerChunk - 1) / kPixelsPerChunk;
  auto chunk_pixels = [&](size_t c) {
    const size_t begin = c * kPixelsPerChunk;
    return pixels.subspan(begin, std::min(kPixelsPerChunk, pixels.size() - begin));
  };
  run_chunks<Slot>(
      chunks,
      [&](size_t c, Slot& s) {
        const std::span<const uint32_t> mine = chunk_pixels(c);
        s.log.clear();
        s.log.set_needs(backend.replay_needs());
        std::unique_ptr<Worker>& w = workers.local();
        if (!w) w = std::make_unique<Worker>(scene, params, image, camera, out);
        w->recorder.set_log(&s.log);
        FrameResult& frame = w->frame;
        frame.rays_by_kind = {};
        w->tracer.render_pixels(camera, mine, frame);
        s.rays_by_kind = frame.rays_by_kind;
        s.radiance.resize(mine.size());
        for (size_t i = 0; i < mine.size(); ++i) s.radiance[i] = frame.radiance[mine[i]];
      },
      [&](size_t c, Slot& s) {
        backend.replay(s.log);
        const std::span<const uint32_t> mine = chunk_pixels(c);
        for (size_t i = 0; i < mine.size(); ++i) out.radiance[mine[i]] = s.radiance[i];
        for (int k = 0; k < kRayKinds; ++k) out.rays_by_kind[k] += s.rays_by_kind[k];
      });
}

}  // namespace

int parallel_threads() {
  return static_cast<int>(
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

ParallelBackend::ParallelBackend(TraceBackend& inner) : inner_(inner) {
  if (!inner.replay_image()) throw std::logic_error("ParallelBackend over a backend without replay");
}

void ParallelBackend::trace(std::span<const RayRecord> rays, std::span<Hit> hits) {
  const MemoryImage& image = *inner_.replay_image();
  const size_t chunks = (rays.size() + kRaysPerChunk - 1) / kRaysPerChunk;
  // An order-free backend: chunks traced in per-thread copies of it, summed at the end.
  if (chunks > 1 && inner_.fork() != nullptr) {
    tbb::enumerable_thread_specific<std::unique_ptr<TraceBackend>> copies(
        [&] { return inner_.fork(); });
    tbb::parallel_for(size_t{0}, chunks, [&](size_t c) {
      const size_t begin = c * kRaysPerChunk;
      const size_t n = std::min(kRaysPerChunk, rays.size() - begin);
      copies.local()->trace(rays.subspan(begin, n), hits.subspan(begin, n));
    });
    for (const std::unique_ptr<TraceBackend>& copy : copies) inner_.join(*copy);
    return;
  }
  run_chunks<FetchLog>(
      chunks,
      [&](size_t c, FetchLog& log) {
        const size_t begin = c * kRaysPerChunk;
        const size_t n = std::min(kRaysPerChunk, rays.size() - begin);
        log.clear();
        log.set_needs(inner_.replay_needs());
        RecordingBackend recorder(image, &log);
        recorder.trace(rays.subspan(begin, n), hits.subspan(begin, n));
      },
      [&](size_t, FetchLog& log) { inner_.replay(log); });
}

void parallel_render_pixels(const Scene& scene, const TracerParams& params,
                            TraceBackend& backend, const PinholeCamera& camera,
                            std::span<const uint32_t> pixels, FrameResult& out) {
  if (parallel_threads() > 1 && backend.replay_image()) {
    if (params.order == RayOrder::kRecursive) {
      render_recursive_parallel(scene, params, backend, camera, pixels, out);
      return;
    }
    ParallelBackend parallel(backend);
    WhittedTracer tracer(scene, params, parallel);
    tracer.begin_frame(camera, out.width, out.height);
    tracer.render_pixels(camera, pixels, out);
    return;
  }
  WhittedTracer tracer(scene, params, backend);  // today's single-thread path
  tracer.begin_frame(camera, out.width, out.height);
  tracer.render_pixels(camera, pixels, out);
}

FrameResult parallel_render(const Scene& scene, const TracerParams& params, TraceBackend& backend,
                            const PinholeCamera& camera, int width, int height,
                            std::span<const uint32_t> order) {
  FrameResult out = WhittedTracer(scene, params, backend).begin_frame(camera, width, height);
  if (!order.empty()) {
    parallel_render_pixels(scene, params, backend, camera, order, out);
    return out;
  }
  std::vector<uint32_t> pixels(out.radiance.size());
  std::iota(pixels.begin(), pixels.end(), 0u);  // scan order
  parallel_render_pixels(scene, params, backend, camera, pixels, out);
  return out;
}

}  // namespace rtusim
