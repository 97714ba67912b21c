// Depth-first layout (pbrt): 8-byte nodes in depth-first order, the below child right after its
// parent, one pointer to the above child.
#pragma once
#include <cstdint>

#include "layout/layout.h"
#include "layout/node_view.h"

namespace rtusim {

// Node encoding (two little-endian u32 words, pbrt-v4's KdTreeNode):
//   word0 bits [1:0]  axis 0..2 for an interior node, 3 for a leaf
//   word0 bits [31:2] interior: index of the above child in the node region;
//                     leaf: number of triangles
//   word1             interior: split position (f32);
//                     leaf: 0 triangles -> 0, 1 -> the triangle id, 2+ -> first list entry index
class DflLayout final : public Layout {
 public:
  static constexpr uint32_t kNodeBytes = 8;
  std::string_view name() const override { return "dfl"; }
  MemoryImage build_image(const KdTree& tree, const Scene& scene) const override;

  // Decodes the node at `addr` of an image this layout wrote.
  static NodeView decode(const MemoryImage& image, uint64_t addr) {
    const uint64_t raw = image.load<uint64_t>(addr);
    const uint32_t w0 = static_cast<uint32_t>(raw), w1 = static_cast<uint32_t>(raw >> 32);
    NodeView v;
    v.axis = w0 & 3u;
    v.leaf = v.axis == 3u;
    if (v.leaf) {
      v.prim_count = w0 >> 2;
      v.inline_prim = w1;
      v.list_addr = image.lists.base_addr + uint64_t{w1} * sizeof(uint32_t);
    } else {
      std::memcpy(&v.split, &w1, sizeof(float));
      v.below_addr = addr + kNodeBytes;
      v.above_addr = image.nodes.base_addr + uint64_t{w0 >> 2} * kNodeBytes;
    }
    return v;
  }
};

}  // namespace rtusim
