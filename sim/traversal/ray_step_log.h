// The traversals of a run of rays as a model of rays in flight takes them: per ray its steps in
// order, each its node fetch and, for a leaf, its list fetch and triangle fetches (one triangle
// test each). A ray's traversal depends neither on the caches nor on the other rays in flight,
// so it is recorded whole, ahead of the model: the timed interleaved mode (TimedInterleaver)
// records runs of rays on any thread and times them on one; the cycle tier's traversal unit and
// the functional tier's round-robin mode record each ray when it starts (one ray's traversal in
// one go, not step by step among the other rays in flight, where the host's branch predictors
// lose the pattern).
// One 64-bit word a fetch: bits 0-1 its kind, bits 2-20 its bytes, bits 21-63 its address; a
// fetch whose bytes or address do not fit is a word with every bytes bit set, then its address
// and its bytes in two more words.
#pragma once
#include <cstddef>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "layout/memory_image.h"
#include "traversal/traversal.h"

namespace rtusim {

class RayStepLog {
 public:
  // A fetch's kind: a step begins with its node's (interior or leaf); a leaf's list and
  // triangles follow it.
  enum class Kind : uint8_t { kInterior = 0, kLeaf = 1, kList = 2, kTriangle = 3 };
  struct Fetch {
    Kind kind;
    uint64_t addr;
    uint32_t bytes;
    Stream stream() const {
      return kind == Kind::kList       ? Stream::kList
             : kind == Kind::kTriangle ? Stream::kTriangle
                                       : Stream::kNode;
    }
  };

  void clear() {
    words_.clear();
    rays_.clear();
    fetches_ = {};
  }

  // Fetches per stream (index: Stream).
  using StreamFetches = std::array<uint64_t, 3>;
  // Fetches recorded since clear().
  const StreamFetches& fetches() const { return fetches_; }

  // Traverses `ray` (a RayRecord: its ray, any_hit() and pixel) through `image` and appends
  // its steps; returns its hit. `after_step` is called with the ray's state after each step.
  template <class Decoder, class Record, class AfterStep = decltype([](const TraversalState&) {})>
  Hit record(const MemoryImage& image, const Record& ray, AfterStep after_step = {}) {
    TraversalState s;
    traversal_begin(s, image, ray.ray, ray.any_hit());
    Sink sink{this};
    while (!s.done) {
      const size_t node_word = words_.size();
      if (traversal_step<Decoder>(s, image, sink) == StepKind::kLeaf)
        words_[node_word] |= static_cast<uint64_t>(Kind::kLeaf);
      after_step(s);
    }
    rays_.push_back({static_cast<uint32_t>(words_.size()), ray.pixel});
    return s.hit;
  }

  size_t ray_count() const { return rays_.size(); }
  uint32_t pixel(size_t i) const { return rays_[i].pixel; }
  // Ray i's words (none: it missed the scene's bounds and took no step).
  std::span<const uint64_t> ray(size_t i) const {
    const uint32_t begin = i ? rays_[i - 1].end : 0;
    return {words_.data() + begin, rays_[i].end - begin};
  }

  static Kind kind(uint64_t word) { return static_cast<Kind>(word & 3); }
  static bool is_node(uint64_t word) { return (word & 3) <= uint64_t(Kind::kLeaf); }
  // Sends the step whose node fetch `p` points at to `sink` (fetch(stream, addr, bytes)): its
  // node fetch, then a leaf's list and triangle fetches; `p` moves past it (`end`: the ray's
  // end). Returns the node's kind.
  template <class Sink>
  [[gnu::always_inline]] static Kind take_step(const uint64_t*& p, const uint64_t* end,
                                               Sink& sink) {
    const Fetch node = next(p);
    sink.fetch(Stream::kNode, node.addr, node.bytes);
    if (node.kind == Kind::kLeaf)
      while (p != end && !is_node(*p)) {
        const Fetch f = next(p);
        sink.fetch(f.stream(), f.addr, f.bytes);
      }
    return node.kind;
  }

  // The fetch whose first word `p` points at; `p` moves past it.
  static Fetch next(const uint64_t*& p) {
    const uint64_t w = *p++;
    const uint32_t bytes = static_cast<uint32_t>(w >> kBytesShift) & kLongBytes;
    if (bytes != kLongBytes) [[likely]]
      return {kind(w), w >> kAddrShift, bytes};
    const Fetch f{kind(w), p[0], static_cast<uint32_t>(p[1])};
    p += 2;
    return f;
  }

 private:
  static constexpr int kBytesShift = 2;
  static constexpr int kAddrShift = 21;
  static constexpr uint32_t kLongBytes = (1u << (kAddrShift - kBytesShift)) - 1;

  // The traversal's sink: a node fetch is recorded as an interior one until its step says leaf.
  struct Sink {
    RayStepLog* log;
    void fetch(Stream s, uint64_t addr, uint32_t bytes) {
      const Kind k = s == Stream::kList       ? Kind::kList
                     : s == Stream::kTriangle ? Kind::kTriangle
                                              : Kind::kInterior;
      log->put(k, addr, bytes);
    }
  };
  void put(Kind k, uint64_t addr, uint32_t bytes) {
    ++fetches_[static_cast<int>(Fetch{k, 0, 0}.stream())];
    if (bytes < kLongBytes && addr >> (64 - kAddrShift) == 0) [[likely]] {
      words_.push_back(addr << kAddrShift | uint64_t{bytes} << kBytesShift | uint64_t(k));
      return;
    }
    words_.push_back(uint64_t{kLongBytes} << kBytesShift | uint64_t(k));
    words_.push_back(addr);
    words_.push_back(bytes);
  }

  struct RayEnd {
    uint32_t end;  // offset in words_ past the ray's last word
    uint32_t pixel;
  };
  std::vector<uint64_t> words_;
  std::vector<RayEnd> rays_;
  StreamFetches fetches_{};
};

}  // namespace rtusim
