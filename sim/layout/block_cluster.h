// What the probability- and profile-guided layouts share: 8-byte nodes clustered eight to a
// 64-byte block by a greedy treelet packer, and a node encoding whose child references are
// 3-bit slots inside the block and global node indices outside it.
//
// Node slot s occupies node-region bytes [8s, 8s + 8); block b holds slots 8b .. 8b + 7, so a
// node never straddles a 64-byte block. The root is slot 0.
//
// Node encoding (two little-endian u32 words; DFL's leaf words):
//   word0 bits [1:0]  axis 0..2 for an interior node, 3 for a leaf
//   interior:
//     word0 bits [3:2]  mode, where the children are:
//       0: both in this block:  bits [6:4] slot of below, bits [9:7] slot of above (in block)
//       1: below in this block: bits [6:4] its slot in block; bits [31:7] global slot of above
//       2: above in this block: bits [6:4] its slot in block; bits [31:7] global slot of below
//       3: neither:             bits [31:4] global slot of below; above at the next slot
//     word1             split position (f32)
//   leaf:
//     word0 bits [31:2] number of triangles
//     word1             0 triangles -> 0, 1 -> the triangle id, 2+ -> first list entry index
// Limits: 2^25 node slots (modes 1 and 2), i.e. 256 MB of nodes.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "kdtree/kd_tree.h"
#include "layout/depth_first_writer.h"
#include "layout/layout.h"
#include "layout/node_view.h"

namespace rtusim {

struct BlockCluster {
  static constexpr uint32_t kNodeBytes = 8;
  static constexpr uint32_t kBlockBytes = 64;
  static constexpr uint32_t kSlotsPerBlock = kBlockBytes / kNodeBytes;  // 8
  static constexpr uint64_t kMaxSlots = uint64_t{1} << 25;

  // Decodes the node at `addr` of an image a block-cluster layout wrote.
  static NodeView decode(const MemoryImage& image, uint64_t addr) {
    NodeView v;
    uint32_t w0;
    if (decode_depth_first_common(image, addr, v, w0)) return v;
    const uint64_t base = image.nodes.base_addr;
    const uint64_t block = base + ((addr - base) & ~uint64_t{kBlockBytes - 1});
    const uint64_t local = block + uint64_t{(w0 >> 4) & 7u} * kNodeBytes;
    switch ((w0 >> 2) & 3u) {
      case 0:
        v.below_addr = local;
        v.above_addr = block + uint64_t{(w0 >> 7) & 7u} * kNodeBytes;
        break;
      case 1:
        v.below_addr = local;
        v.above_addr = base + uint64_t{w0 >> 7} * kNodeBytes;
        break;
      case 2:
        v.above_addr = local;
        v.below_addr = base + uint64_t{w0 >> 7} * kNodeBytes;
        break;
      default:
        v.below_addr = base + uint64_t{w0 >> 4} * kNodeBytes;
        v.above_addr = v.below_addr + kNodeBytes;
        break;
    }
    return v;
  }

  // Greedy treelet packing: returns the slot of every node, `slots` the slots used.
  //
  // A block starts from a pending root (one node, or two siblings whose parent lies in another
  // block, kept side by side) and grows: it repeatedly takes, among the nodes whose parent is
  // already in the block, the one of highest `priority` (ties: the lower node index), until its
  // eight slots are full. What still hangs below a full block becomes pending roots (siblings
  // hanging together as one pair root), the most likely placed next, so blocks follow the tree
  // depth first. A block whose treelet runs out takes the next pending root into its free
  // slots (a pair only into two; else a single root from the next few, else a padding slot).
  static std::vector<uint32_t> pack(const KdTree& tree, const std::vector<double>& priority,
                                    uint64_t& slots);

  // Serialises `tree` as `name` with node i at slot `slot_of[i]` (a packing by pack()).
  static MemoryImage write(const KdTree& tree, const Scene& scene, const std::string& name,
                           const std::vector<uint32_t>& slot_of, uint64_t slots);
};

}  // namespace rtusim
