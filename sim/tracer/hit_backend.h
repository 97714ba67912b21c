// Traces ray batches on the host for their hits alone: no fetch is counted or kept, so packets
// skip reporting them. For runs that need every ray's hit but model nothing of the traversal
// (the sampled wavefront's whole-frame tracing: the tier measures the drawn units itself).
#pragma once
#include <memory>

#include "layout/memory_image.h"
#include "tracer/trace_backend.h"

namespace rtusim {

class HitBackend final : public TraceBackend {
 public:
  explicit HitBackend(const MemoryImage& image) : image_(image) {}
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override;
  // Parallel tracing (ParallelBackend) takes it like any backend: replay has nothing to do.
  const MemoryImage* replay_image() const override { return &image_; }
  void replay(const FetchLog& /*log*/) override {}
  std::unique_ptr<TraceBackend> fork() const override {
    return std::make_unique<HitBackend>(image_);
  }

 private:
  const MemoryImage& image_;
};

}  // namespace rtusim
