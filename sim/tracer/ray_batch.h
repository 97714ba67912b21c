// The host <-> traversal seam: the tracer hands out batches of rays and takes back their hits.
// The host backend traverses them at once; the SystemC unit consumes the same batches.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "geom/ray.h"

namespace rtusim {

class FetchLog;
struct MemoryImage;

enum class RayKind : uint8_t { kPrimary = 0, kShadow = 1, kReflection = 2, kRefraction = 3 };
constexpr int kRayKinds = 4;

struct RayRecord {
  Ray ray;
  RayKind kind = RayKind::kPrimary;
  uint32_t pixel = 0;  // the pixel whose ray tree this ray belongs to
  bool any_hit() const { return kind == RayKind::kShadow; }
};

// Something that traces ray batches: hits[i] is the hit of rays[i].
class TraceBackend {
 public:
  virtual ~TraceBackend() = default;
  virtual void trace(std::span<const RayRecord> rays, std::span<Hit> hits) = 0;

  // A backend whose state depends only on its rays' fetches (caches, recorders) can take rays
  // traversed elsewhere (tracer/parallel_render.h): it names the image to traverse, and
  // replay() then does what trace() of the log's rays would have done. nullptr: trace() only.
  virtual const MemoryImage* replay_image() const { return nullptr; }
  virtual void replay(const FetchLog& log);

  // A backend whose state is a sum over its rays, whatever their order (counters), can instead
  // trace on other threads in copies of itself: fork() makes an empty copy (nullptr: it
  // cannot), join() adds a copy's state to this one's.
  virtual std::unique_ptr<TraceBackend> fork() const { return nullptr; }
  virtual void join(const TraceBackend& /*copy*/) {}
};

}  // namespace rtusim
