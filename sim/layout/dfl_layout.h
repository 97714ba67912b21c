// Depth-first layout (pbrt): 8-byte nodes in depth-first order, the below child right after its
// parent, one pointer to the above child.
#pragma once
#include <cstdint>

#include "layout/layout.h"
#include "layout/depth_first_writer.h"
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
  static constexpr const char* kName = "dfl";
  std::string_view name() const override { return kName; }
  MemoryImage build_image(const KdTree& tree, const Scene& scene) const override;

  // Decodes the node at `addr` of an image this layout wrote.
  static NodeView decode(const MemoryImage& image, uint64_t addr) {
    NodeView v;
    uint32_t w0;
    if (decode_depth_first_common(image, addr, v, w0)) return v;
    v.below_addr = addr + kNodeBytes;
    v.above_addr = image.nodes.base_addr + uint64_t{w0 >> 2} * kNodeBytes;
    return v;
  }
};

}  // namespace rtusim
