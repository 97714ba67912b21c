// A fetch sink for traversal_step() that records a step's fetches, for a model that sends them
// on later at their own times (the traversal unit, the timed interleaved functional mode).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "layout/memory_image.h"

namespace rtusim {

// One fetch as traversal_step() reported it.
struct RecordedFetch {
  Stream stream;
  uint64_t addr;
  uint32_t bytes;
};

// Where a leaf step's triangle fetches begin: traversal_step() reports the leaf's node, then its
// triangle list when it has one, then its triangles.
inline size_t first_triangle_fetch(const std::vector<RecordedFetch>& step) {
  return step.size() > 1 && step[1].stream == Stream::kList ? 2 : 1;
}

// Appends each fetch to `out`, in issue order.
struct FetchRecorder {
  std::vector<RecordedFetch>* out;
  void fetch(Stream s, uint64_t addr, uint32_t bytes) { out->push_back({s, addr, bytes}); }
};

}  // namespace rtusim
