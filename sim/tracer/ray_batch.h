// The host <-> traversal seam: the tracer hands out batches of rays and takes back their hits.
// The host backend traverses them at once; the SystemC unit consumes the same batches.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "geom/ray.h"

namespace rtusim {

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
};

}  // namespace rtusim
