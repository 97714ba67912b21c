// A record of the fetches of a run of rays, in issue order, for tracing rays on other threads
// and applying their fetches to a cache model later in the single-thread order. Each fetch is
// one 64-bit word: the address in the high 40 bits, the size in the next 22 and the stream in
// the low 2 (8 bytes a fetch instead of the 16 of a RecordedFetch). A fetch that does not fit
// (an address at or past 2^40 or a size at or past 2^22, which no image of this simulator
// reaches) takes three words: a marker (stream code 3), the address and the size with its
// stream. Words, not a varint stream: recording and replay are a store and a load with no
// data-dependent branch, where the varints' byte-by-byte decode cost more per fetch than the
// cache model it fed (the replay runs on one thread, so it bounds every parallel run).
//
// What the replaying backend does not need (ReplayNeeds) is counted while recording instead:
// node fetches that can only be repeated hits on the line the node stream touched last, and
// list and triangle fetches that go straight to DRAM (their bursts, charged to their ray).
// A log starts counting afresh at clear(): the first node fetch after it is always logged.
#pragma once
#include <array>
#include <bit>
#include <cstdint>
#include <vector>

#include "cache/fetch_cache.h"
#include "layout/memory_image.h"
#include "tracer/trace_backend.h"

namespace rtusim {

class FetchLog {
 public:
  // What is counted instead of logged, from the next fetch on (kept by clear()).
  void set_needs(const ReplayNeeds& needs) {
    node_line_shift_ = needs.node_line_bytes ? std::countr_zero(needs.node_line_bytes) : -1;
    direct_ = needs.lists_triangles_direct;
    burst_bytes_ = needs.dram_burst_bytes;
  }

  // The traversal sink call: records one fetch of the current ray.
  [[gnu::always_inline]] void fetch(Stream s, uint64_t addr, uint32_t bytes) {
    if (bytes != 0) {
      if (s == Stream::kNode) {
        if (node_line_shift_ >= 0 && counted_node_hit(addr, bytes)) return;
      } else if (direct_) {
        const uint64_t bursts = FetchCache::dram_bursts(addr, bytes, burst_bytes_);
        DirectCount& d = direct_counts_[static_cast<int>(s)];
        ++d.fetches;
        d.bursts += bursts;
        ray_direct_bytes_ += bursts * burst_bytes_;
        return;
      }
    }
    if (words_.size() - used_ < kMaxWordsPerFetch) [[unlikely]] grow();
    uint64_t* w = words_.data() + used_;
    const auto stream = static_cast<uint64_t>(s);
    if ((addr >> kAddrBits) == 0 && (bytes >> kSizeBits) == 0) [[likely]] {
      *w = addr << (kSizeBits + 2) | uint64_t{bytes} << 2 | stream;
      ++used_;
      return;
    }
    w[0] = kLongMarker;
    w[1] = addr;
    w[2] = uint64_t{bytes} << 2 | stream;
    used_ += 3;
  }
  // Closes the current ray: the fetches since the last end_ray() are `ray`'s.
  void end_ray(const RayRecord& ray) {
    rays_.push_back({ray.pixel, ray.kind, static_cast<uint32_t>(used_), ray_direct_bytes_});
    ray_direct_bytes_ = 0;
  }
  void clear();

  size_t ray_count() const { return rays_.size(); }
  uint64_t ray_count(RayKind kind) const {
    uint64_t n = 0;
    for (const RayEnd& r : rays_) n += r.kind == kind;
    return n;
  }
  size_t size_bytes() const { return used_ * sizeof(uint64_t) + rays_.size() * sizeof(RayEnd); }

  // Counted, not logged: node fetches that were repeated hits (each one line access), and per
  // stream the fetches straight to DRAM and their DRAM bursts.
  struct DirectCount {
    uint64_t fetches = 0;
    uint64_t bursts = 0;
  };
  uint64_t counted_node_hits() const { return counted_node_hits_; }
  const std::array<DirectCount, FetchCache::kStreams>& direct_counts() const {
    return direct_counts_;
  }

  // Calls sink.fetch(stream, addr, bytes) for every logged fetch in issue order, and after each
  // ray's fetches sink.end_ray(pixel, kind, direct_dram_bytes), the last being the DRAM bytes
  // of the ray's fetches that were counted instead of logged.
  template <class Sink>
  void replay(Sink& sink) const {
    const uint64_t* w = words_.data();
    size_t pos = 0;
    for (const RayEnd& r : rays_) {
      while (pos < r.end) {
        const uint64_t word = w[pos];
        if (word != kLongMarker) [[likely]] {
          sink.fetch(static_cast<Stream>(word & 3), word >> (kSizeBits + 2),
                     static_cast<uint32_t>(word >> 2) & ((1u << kSizeBits) - 1));
          ++pos;
        } else {
          sink.fetch(static_cast<Stream>(w[pos + 2] & 3), w[pos + 1],
                     static_cast<uint32_t>(w[pos + 2] >> 2));
          pos += 3;
        }
      }
      sink.end_ray(r.pixel, r.kind, r.direct_bytes);
    }
  }

 private:
  static constexpr int kAddrBits = 40;  // byte addresses below 1 TiB fit a short record
  static constexpr int kSizeBits = 22;  // sizes below 4 MiB fit a short record
  static constexpr uint64_t kLongMarker = 3;  // stream code 3: a long record follows
  static constexpr size_t kMaxWordsPerFetch = 3;
  static constexpr uint64_t kNoLine = ~uint64_t{0};
  struct RayEnd {
    uint32_t pixel;
    RayKind kind;
    uint32_t end;           // index in words_ past the ray's last logged fetch
    uint64_t direct_bytes;  // DRAM bytes of its counted fetches straight to DRAM
  };

  // A node fetch of `bytes` (> 0) at `addr`: whether it lies in the line the node stream's
  // previous fetch ended in (a repeated hit, now counted); else it becomes the last line.
  bool counted_node_hit(uint64_t addr, uint64_t bytes) {
    const uint64_t first = addr >> node_line_shift_;
    const uint64_t last = (addr + bytes - 1) >> node_line_shift_;
    if (first == last && first == last_node_line_) {
      ++counted_node_hits_;
      return true;
    }
    last_node_line_ = last;
    return false;
  }
  [[gnu::noinline]] void grow() { words_.resize(2 * words_.size() + 1024); }

  std::vector<uint64_t> words_;  // the records in [0, used_); the rest is room to write
  size_t used_ = 0;
  std::vector<RayEnd> rays_;
  int node_line_shift_ = -1;  // -1: every node fetch logged
  bool direct_ = false;
  uint32_t burst_bytes_ = ReplayNeeds{}.dram_burst_bytes;  // set_needs()' (used with direct_)
  uint64_t last_node_line_ = kNoLine;
  uint64_t counted_node_hits_ = 0;
  std::array<DirectCount, FetchCache::kStreams> direct_counts_{};
  uint64_t ray_direct_bytes_ = 0;  // of the ray being recorded
};

}  // namespace rtusim
