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

// What a backend's replay() needs of a FetchLog, so that the recording, on the worker threads,
// counts the fetches whose effect does not depend on the backend's state instead of logging
// them for the single replay thread.
struct ReplayNeeds {
  // Nonzero: the node L1's line bytes, for a backend whose node L1 takes a repeated hit on its
  // last-touched line without changing any later decision (ReplacementPolicy::
  // retouch_neutral()): a node fetch within the line the previous node fetch ended in is then
  // such a hit, counted, not logged. 0: every node fetch is logged.
  uint32_t node_line_bytes = 0;
  // List and triangle fetches go straight to DRAM: their bursts (of dram_burst_bytes) are
  // counted, not logged.
  bool lists_triangles_direct = false;
  uint32_t dram_burst_bytes = 64;  // FetchCache's burst (default: FetchCacheParams')
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
  // What replay() needs recorded (default: every fetch).
  virtual ReplayNeeds replay_needs() const { return {}; }

  // A backend whose state is a sum over its rays, whatever their order (counters), can instead
  // trace on other threads in copies of itself: fork() makes an empty copy (nullptr: it
  // cannot), join() adds a copy's state to this one's.
  virtual std::unique_ptr<TraceBackend> fork() const { return nullptr; }
  virtual void join(const TraceBackend& /*copy*/) {}
};

}  // namespace rtusim
