// Ordinary subtree layout (Havran 1999; Havran's thesis, 2000, on kd-tree memory layouts):
// 12-byte nodes with both child references explicit, clustered into 64-byte blocks of five
// nodes, each block a connected subtree of the kd-tree or, where a subtree runs out, several
// small subtrees sharing the block. Two clusterings:
//   subtree      full blocks: the study's layout, about 1.6x DFL's node bytes
//   subtree-bfs  one subtree per block: the earlier, top-down-only clustering (blocks about
//                half full, about 3x DFL's bytes), kept for comparison
// Why full blocks: Havran stores a kd-tree in cache-line blocks so that one line fetch serves
// several traversal steps, and counts its memory as five 12-byte nodes per 64-byte block; the
// study's "~40% more memory than ODFL" (1.6x) is that count. Giving every hanging node its own
// block (subtree-bfs) instead leaves the bottom of the tree one or two nodes per block, which
// the layout as described does not do; so small subtrees share blocks.
#pragma once
#include <cstdint>
#include <cstring>

#include "layout/layout.h"
#include "layout/node_view.h"

namespace rtusim {

// Clustering: top-down. A block takes its root, then fills breadth-first (children below before
// above) until it holds five nodes or its subtree is exhausted; every node left hanging below
// the block roots a new block. With shared blocks (subtree), a hanging node whose whole subtree
// has fewer than five nodes (one leaf, or a node with two leaves) does not root a block of its
// own: the subtree goes whole, breadth-first, into the first of the last kSharedSearch shared
// blocks it fits in (else a new one), shared blocks taking the small subtrees in the order they
// come, so neighbours in the tree share. A subtree of five or more nodes fills its own block.
// Blocks are numbered as they are opened: a block, then (shared blocks) the ones opened for its
// small hanging subtrees, then the blocks rooted at its other hanging nodes in breadth-first
// order, each recursively (depth-first pre-order of the block tree).
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
class SubtreeLayout : public Layout {
 public:
  static constexpr uint32_t kNodeBytes = 12;
  static constexpr uint32_t kBlockBytes = 64;
  static constexpr uint32_t kNodesPerBlock = kBlockBytes / kNodeBytes;  // 5
  static constexpr uint32_t kSlotBits = 3;
  static constexpr size_t kSharedSearch = 8;  // shared blocks a small subtree may go into
  static_assert(kNodesPerBlock == 5 && kNodesPerBlock <= (1u << kSlotBits));

  static constexpr const char* kName = "subtree";
  // `shared_blocks`: fill every block (subtree); false: one subtree per block (subtree-bfs).
  explicit SubtreeLayout(bool shared_blocks = true) : shared_blocks_(shared_blocks) {}
  std::string_view name() const override;  // kName, or SubtreeBfsLayout::kName
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

 private:
  bool shared_blocks_;
};

}  // namespace rtusim
