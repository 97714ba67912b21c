// The memory image of a laid-out tree: the bytes a traversal unit fetches, at real addresses.
#pragma once
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace rtusim {

// The three fetch streams of a traversal: nodes, leaf primitive lists and triangles.
enum class Stream : uint8_t { kNode = 0, kList = 1, kTriangle = 2 };

// A contiguous, 64-byte aligned range of the image.
struct Region {
  uint64_t base_addr = 0;
  uint64_t size_bytes = 0;
  uint64_t end_addr() const { return base_addr + size_bytes; }
};

// Bytes at addresses [0, bytes.size()). Regions are 64-byte aligned; nodes come first.
struct MemoryImage {
  static constexpr uint64_t kRegionAlign = 64;
  static constexpr uint32_t kTriangleBytes = 36;  // three float3 vertices

  std::string layout;  // name of the layout that wrote it ("dfl", ...)
  std::vector<uint8_t> bytes;
  Region nodes, lists, triangles;
  uint64_t root_addr = 0;
  uint32_t node_bytes = 8;
  float bounds_min[3] = {0, 0, 0}, bounds_max[3] = {0, 0, 0};  // scene bounds the tree covers

  template <class T>
  T load(uint64_t addr) const {
    T v;
    std::memcpy(&v, bytes.data() + addr, sizeof(T));
    return v;
  }
  template <class T>
  void store(uint64_t addr, const T& v) {
    std::memcpy(bytes.data() + addr, &v, sizeof(T));
  }
  uint64_t triangle_addr(uint32_t tri) const {
    return triangles.base_addr + uint64_t{tri} * kTriangleBytes;
  }
};

// Rounds `addr` up to the region alignment.
inline uint64_t align_region(uint64_t addr) {
  return (addr + MemoryImage::kRegionAlign - 1) & ~(MemoryImage::kRegionAlign - 1);
}

}  // namespace rtusim
