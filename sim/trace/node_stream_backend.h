// A TraceBackend that records the node-fetch address stream: it traverses every ray batch the
// tracer hands it (the whole Whitted frame, in the configured ray order) through the same
// traversal step as the functional tier, and passes each node fetch address, in issue order, to
// a recorder. Lists and triangles are fetched but not recorded.
#pragma once
#include <cstdint>

#include "layout/memory_image.h"
#include "tracer/trace_backend.h"

namespace rtusim {

// Receives node fetch addresses in issue order.
class NodeStreamRecorder {
 public:
  virtual ~NodeStreamRecorder() = default;
  virtual void node_fetch(uint64_t addr) = 0;
};

class NodeStreamBackend final : public TraceBackend {
 public:
  NodeStreamBackend(const MemoryImage& image, NodeStreamRecorder& recorder)
      : image_(image), recorder_(recorder) {}
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override;
  const MemoryImage* replay_image() const override { return &image_; }
  void replay(const FetchLog& log) override;

 private:
  const MemoryImage& image_;
  NodeStreamRecorder& recorder_;
};

}  // namespace rtusim
