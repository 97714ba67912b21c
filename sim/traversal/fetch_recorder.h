// A fetch sink for traversal_step() that records a step's fetches, for a model that sends them
// on later at their own times (the traversal unit, the timed interleaved functional mode).
#pragma once
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

// Appends each fetch to `out`, in issue order.
struct FetchRecorder {
  std::vector<RecordedFetch>* out;
  void fetch(Stream s, uint64_t addr, uint32_t bytes) { out->push_back({s, addr, bytes}); }
};

}  // namespace rtusim
