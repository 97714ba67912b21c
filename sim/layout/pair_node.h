// What the sibling-pair layouts (veb, cluster, profile) share: 8-byte nodes whose two children
// sit side by side in one 16-byte aligned "pair unit" (Wald's kd-tree node, 2004), so a node
// needs one reference for both children and a layout is free to put each pair unit anywhere.
// The layouts differ only in where they put the pair units.
//
// Pair unit u occupies node-region bytes [16u, 16u + 16): slot 0 the below child, slot 1 the
// above child. Unit 0 holds the root in slot 0; its slot 1 is padding (zero). A unit never
// straddles a 16-, 32- or 64-byte line, so neither does a node.
//
// Node encoding (two little-endian u32 words; DFL's leaf words):
//   word0 bits [1:0]  axis 0..2 for an interior node, 3 for a leaf
//   interior:
//     word0 bits [31:2] index u of the children's pair unit (30 bits): below child at
//                       nodes.base_addr + 16u, above child at nodes.base_addr + 16u + 8
//     word1             split position (f32)
//   leaf:
//     word0 bits [31:2] number of triangles
//     word1             0 triangles -> 0, 1 -> the triangle id, 2+ -> first list entry index
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "layout/depth_first_writer.h"
#include "layout/layout.h"
#include "layout/node_view.h"
#include "layout/node_word_writer.h"
#include "util/error.h"

namespace rtusim {

struct PairNode {
  static constexpr uint32_t kNodeBytes = 8;
  static constexpr uint32_t kUnitBytes = 16;
  static constexpr uint64_t kMaxUnits = uint64_t{1} << 30;

  // Decodes the node at `addr` of an image a pair layout wrote.
  static NodeView decode(const MemoryImage& image, uint64_t addr) {
    NodeView v;
    uint32_t w0;
    if (decode_depth_first_common(image, addr, v, w0)) return v;
    v.below_addr = image.nodes.base_addr + uint64_t{w0 >> 2} * kUnitBytes;
    v.above_addr = v.below_addr + kNodeBytes;
    return v;
  }
};

// Serialises `tree` as `name`: `unit_of[i]` is the pair unit holding the children of interior
// node i (ignored for leaves; units from 1, unit 0 is the root's); `units` is the number of
// units the node region spans (rounded up to whole 64-byte blocks).
inline MemoryImage write_pair_image(const KdTree& tree, const Scene& scene,
                                    const std::string& name, const std::vector<uint32_t>& unit_of,
                                    uint64_t units) {
  if (units > PairNode::kMaxUnits)
    throw InputError("layout " + name + ": tree has " + std::to_string(tree.nodes.size()) +
                     " nodes, more pair units than the 30-bit child index holds");
  // Node offsets: the root at 0, every other node in its parent's pair unit.
  std::vector<uint64_t> offset(tree.nodes.size(), 0);
  for (uint32_t i = 0; i < tree.nodes.size(); ++i) {
    const KdNode& n = tree.nodes[i];
    if (n.is_leaf()) continue;
    offset[n.below] = uint64_t{unit_of[i]} * PairNode::kUnitBytes;
    offset[n.above] = offset[n.below] + PairNode::kNodeBytes;
  }
  return write_8_byte_nodes(tree, scene, name, units * PairNode::kUnitBytes, offset,
                            [&](uint32_t i) { return (unit_of[i] << 2) | tree.nodes[i].axis; });
}

}  // namespace rtusim
