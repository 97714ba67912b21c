// Tracing on every core with exactly the single-thread answer. Hits do not depend on the
// memory model, so chunks of rays (or of pixels, with their whole ray trees) are traversed
// concurrently while each chunk's fetches are recorded in a FetchLog; the logs are then
// replayed into the backend one chunk at a time in the single-thread order. Caches, DRAM
// charges, recorded streams, images and ray counts are therefore identical for any thread
// count. Memory stays bounded: a pipeline keeps at most a few chunks per thread alive.
// The thread count is oneTBB's (tbb::global_control, set by --threads); with one thread, or a
// backend without replay (the cycle and RTL tiers), everything runs on the caller's thread.
#pragma once
#include <cstdint>
#include <span>

#include "scene/pinhole_camera.h"
#include "scene/scene.h"
#include "tracer/trace_backend.h"
#include "tracer/tracer_params.h"
#include "tracer/whitted_tracer.h"

namespace rtusim {

// Threads a parallel render may use (oneTBB's current limit).
int parallel_threads();

// A TraceBackend whose trace() traverses a batch in parallel chunks and replays their fetches
// into `inner` in batch order. `inner` must have a replay_image(). An inner backend that can
// fork() (order-free: counters) has the chunks traced in copies of itself instead, joined into
// it after the batch.
class ParallelBackend final : public TraceBackend {
 public:
  explicit ParallelBackend(TraceBackend& inner);
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override;
  const MemoryImage* replay_image() const override { return inner_.replay_image(); }
  void replay(const FetchLog& log) override { inner_.replay(log); }
  ReplayNeeds replay_needs() const override { return inner_.replay_needs(); }

 private:
  TraceBackend& inner_;
};

// WhittedTracer::render_pixels() on every core with the single-thread result: recursive order
// traces chunks of the list concurrently (each pixel's ray tree in one task), wavefront order
// traces each generation's batches through a ParallelBackend. `out` as for render_pixels().
void parallel_render_pixels(const Scene& scene, const TracerParams& params,
                            TraceBackend& backend, const PinholeCamera& camera,
                            std::span<const uint32_t> pixels, FrameResult& out);

// WhittedTracer::render() on every core with the single-thread result; the pixels in `order`
// (every pixel once) instead of scan order when it is not empty.
FrameResult parallel_render(const Scene& scene, const TracerParams& params, TraceBackend& backend,
                            const PinholeCamera& camera, int width, int height,
                            std::span<const uint32_t> order = {});

}  // namespace rtusim
