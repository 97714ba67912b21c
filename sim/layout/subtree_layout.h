// Ordinary subtree layout (Havran 1999; Havran's thesis, 2000, on kd-tree memory layouts):
// 12-byte nodes with both child references explicit, clustered into 64-byte blocks of up to
// five nodes, each block a connected subtree of the kd-tree.
#pragma once
#include <cstdint>
#include <cstring>

#include "layout/layout.h"
#include "layout/node_view.h"

namespace rtusim {

// Clustering: top-down. A block takes its root, then fills breadth-first (children below before
// above) until it holds five nodes or its subtree is exhausted; every node left hanging below
// the block roots a new block. Blocks are numbered in depth-first pre-order of the block tree:
// a block, then the blocks rooted at its hanging nodes in breadth-first order, each recursively.
// Within a block, slot s holds the s-th node of the breadth-first fill (slot 0 = block root).
//
// Node reference: ref = block << 3 | slot (slot 0..4), node address =
//   nodes.base_addr + 64 * block + 12 * slot,
// so a node never straddles a 64-byte line; bytes 60..63 of each block are padding (zero).
//
// Node encoding (three little-endian u32 words):
//   word0 bits [1:0]  axis 0..2 for an interior node, 3 for a leaf
//   interior:
//     word0 bits [31:2] ref of the below child (30 bits: up to 2^27 blocks)
//     word1             split position (f32)
//     word2             ref of the above child
//   leaf:
//     word0 bits [31:2] number of triangles
//     word1             0 triangles -> 0, 1 -> the triangle id, 2+ -> first list entry index
//     word2             0
class SubtreeLayout final : public Layout {
 public:
  static constexpr uint32_t kNodeBytes = 12;
  static constexpr uint32_t kBlockBytes = 64;
  static constexpr uint32_t kNodesPerBlock = kBlockBytes / kNodeBytes;  // 5
  static constexpr uint32_t kSlotBits = 3;
  static_assert(kNodesPerBlock == 5 && kNodesPerBlock <= (1u << kSlotBits));

  static constexpr const char* kName = "subtree";
  std::string_view name() const override { return kName; }
  MemoryImage build_image(const KdTree& tree, const Scene& scene) const override;

  // Byte offset in the node region of the node with reference `ref`.
  static constexpr uint64_t ref_offset(uint32_t ref) {
    return uint64_t{ref >> kSlotBits} * kBlockBytes +
           uint64_t{ref & ((1u << kSlotBits) - 1)} * kNodeBytes;
  }

  // Decodes the node at `addr` of an image this layout wrote.
  static NodeView decode(const MemoryImage& image, uint64_t addr) {
    uint32_t w[3];
    std::memcpy(w, image.bytes.data() + addr, sizeof w);
    NodeView v;
    v.axis = w[0] & 3u;
    v.leaf = v.axis == 3u;
    if (v.leaf) {
      v.prim_count = w[0] >> 2;
      v.inline_prim = w[1];
      v.list_addr = image.lists.base_addr + uint64_t{w[1]} * sizeof(uint32_t);
    } else {
      std::memcpy(&v.split, &w[1], sizeof(float));
      v.below_addr = image.nodes.base_addr + ref_offset(w[0] >> 2);
      v.above_addr = image.nodes.base_addr + ref_offset(w[2]);
    }
    return v;
  }
};

}  // namespace rtusim
