// A compact record of the fetches of a run of rays, in issue order, for tracing rays on other
// threads and applying their fetches to a cache model later in the single-thread order.
// Each fetch is a tag byte (stream, and whether its size repeats the stream's last one), the
// zigzag varint of its address minus the stream's last address, and its size when it changed:
// about 2-4 bytes a fetch instead of 16.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "layout/memory_image.h"
#include "tracer/ray_batch.h"

namespace rtusim {

class FetchLog {
 public:
  // The traversal sink call: records one fetch of the current ray.
  void fetch(Stream s, uint64_t addr, uint32_t bytes) {
    if (bytes_.size() - used_ < kMaxFetchBytes) bytes_.resize(2 * bytes_.size() + kMaxFetchBytes);
    uint8_t* p = bytes_.data() + used_;
    const int i = static_cast<int>(s);
    const bool same_size = bytes == last_bytes_[i];
    *p++ = static_cast<uint8_t>(i | (same_size ? kSameSize : 0));
    const uint64_t delta = addr - last_addr_[i];
    p = put_varint(p, (delta << 1) ^ (0 - (delta >> 63)));  // zigzag: small steps back stay short
    if (!same_size) p = put_varint(p, bytes);
    used_ = static_cast<size_t>(p - bytes_.data());
    last_addr_[i] = addr;
    last_bytes_[i] = bytes;
  }
  // Closes the current ray: the fetches since the last end_ray() are `ray`'s.
  void end_ray(const RayRecord& ray) {
    rays_.push_back({ray.pixel, ray.kind, static_cast<uint32_t>(used_)});
  }
  void clear();

  size_t ray_count() const { return rays_.size(); }
  uint64_t ray_count(RayKind kind) const {
    uint64_t n = 0;
    for (const RayEnd& r : rays_) n += r.kind == kind;
    return n;
  }
  size_t size_bytes() const { return used_ + rays_.size() * sizeof(RayEnd); }

  // Calls sink.fetch(stream, addr, bytes) for every fetch in issue order, and
  // sink.end_ray(pixel, kind) after each ray's fetches.
  template <class Sink>
  void replay(Sink& sink) const {
    std::array<uint64_t, 3> addr{};
    std::array<uint32_t, 3> size{};
    size_t pos = 0;
    for (const RayEnd& r : rays_) {
      while (pos < r.end) {
        const uint8_t tag = bytes_[pos++];
        const int i = tag & 3;
        const uint64_t z = get_varint(pos);
        addr[i] += (z >> 1) ^ (0 - (z & 1));
        if (!(tag & kSameSize)) size[i] = static_cast<uint32_t>(get_varint(pos));
        sink.fetch(static_cast<Stream>(i), addr[i], size[i]);
      }
      sink.end_ray(r.pixel, r.kind);
    }
  }

 private:
  static constexpr uint8_t kSameSize = 4;
  static constexpr size_t kMaxFetchBytes = 1 + 10 + 5;  // tag, address step, size
  struct RayEnd {
    uint32_t pixel;
    RayKind kind;
    uint32_t end;  // offset in bytes_ past the ray's last fetch
  };

  static uint8_t* put_varint(uint8_t* p, uint64_t v) {
    while (v >= 0x80) {
      *p++ = static_cast<uint8_t>(v | 0x80);
      v >>= 7;
    }
    *p++ = static_cast<uint8_t>(v);
    return p;
  }
  uint64_t get_varint(size_t& pos) const {
    uint64_t v = 0;
    for (int shift = 0;; shift += 7) {
      const uint8_t b = bytes_[pos++];
      v |= uint64_t{b & 0x7fu} << shift;
      if (!(b & 0x80)) return v;
    }
  }

  std::vector<uint8_t> bytes_;  // the encoding in [0, used_); the rest is room to write
  size_t used_ = 0;
  std::vector<RayEnd> rays_;
  std::array<uint64_t, 3> last_addr_{};
  std::array<uint32_t, 3> last_bytes_{};
};

}  // namespace rtusim
