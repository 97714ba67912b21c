// A step's fetches, in order, for a model that sends them on later at their own times: a fetch
// sink for traversal_step() (batch traversal), or filled from a ray's record (the traversal
// unit).
#pragma once
#include <algorithm>
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

// A step's fetches, reused step after step, itself the sink: appending is a store and an
// increment inline (std::vector's push_back, growth path included, is a call per fetch); the
// storage grows out of line on a rare large leaf and is kept.
class FetchList {
 public:
  FetchList() : buf_(kInitial) {}
  void clear() { size_ = 0; }
  size_t size() const { return size_; }
  const RecordedFetch& operator[](size_t i) const { return buf_[i]; }
  [[gnu::always_inline]] void fetch(Stream s, uint64_t addr, uint32_t bytes) {
    if (size_ == buf_.size()) [[unlikely]] grow();
    buf_[size_++] = {s, addr, bytes};
  }

 private:
  static constexpr size_t kInitial = 16;  // a node, a list and most leaves' triangles
  [[gnu::noinline]] void grow() { buf_.resize(std::max(kInitial, 2 * buf_.size())); }
  std::vector<RecordedFetch> buf_;
  size_t size_ = 0;
};

// Where a leaf step's triangle fetches begin: traversal_step() reports the leaf's node, then its
// triangle list when it has one, then its triangles.
inline size_t first_triangle_fetch(const FetchList& step) {
  return step.size() > 1 && step[1].stream == Stream::kList ? 2 : 1;
}

}  // namespace rtusim
