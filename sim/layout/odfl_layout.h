// Ordered depth-first layout (Nah et al. 2010): DFL's 8-byte node and one pointer, but the child
// with the larger surface area is stored right after its parent, and a reorder flag in the node
// says which child that is. No memory beyond DFL's.
#pragma once
#include <cstdint>
#include <cstring>

#include "layout/layout.h"
#include "layout/depth_first_writer.h"
#include "layout/node_view.h"

namespace rtusim {

// Node encoding (two little-endian u32 words; DFL's, with one bit taken for the flag):
//   word0 bits [1:0]  axis 0..2 for an interior node, 3 for a leaf
//   interior:
//     word0 bit 2       reorder flag: 0 = the below child is adjacent (at addr + 8),
//                       1 = the above child is adjacent
//     word0 bits [31:3] index in the node region of the other (non-adjacent) child, 29 bits
//     word1             split position (f32)
//   leaf (as DFL):
//     word0 bits [31:2] number of triangles
//     word1             0 triangles -> 0, 1 -> the triangle id, 2+ -> first list entry index
// The adjacent child is the one whose box (the parent's box cut at the plane) has the larger
// surface area; on a tie, the below child. Nodes are in pre-order, adjacent child first.
class OdflLayout final : public Layout {
 public:
  static constexpr uint32_t kNodeBytes = 8;
  static constexpr uint32_t kReorderBit = 1u << 2;
  static constexpr const char* kName = "odfl";
  std::string_view name() const override { return kName; }
  MemoryImage build_image(const KdTree& tree, const Scene& scene) const override;

  // Decodes the node at `addr` of an image this layout wrote.
  static NodeView decode(const MemoryImage& image, uint64_t addr) {
    NodeView v;
    uint32_t w0;
    if (decode_depth_first_common(image, addr, v, w0)) return v;
    const uint64_t adjacent = addr + kNodeBytes;
    const uint64_t other = image.nodes.base_addr + uint64_t{w0 >> 3} * kNodeBytes;
    const bool above_is_adjacent = (w0 & kReorderBit) != 0;
    v.below_addr = above_is_adjacent ? other : adjacent;
    v.above_addr = above_is_adjacent ? adjacent : other;
    return v;
  }

  // True when the above child of interior node `n` with box `b` is the one stored adjacent.
  static bool above_adjacent(const KdNode& n, const Bounds3f& b) {
    return KdTree::above_bounds(n, b).surface_area() > KdTree::below_bounds(n, b).surface_area();
  }
};

}  // namespace rtusim
