// Writes an image of 8-byte nodes placed anywhere in the node region: what the pair and the
// block-cluster layouts share. Leaf words are DFL's; the layout encodes interior word0.
#pragma once
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "layout/layout.h"

namespace rtusim {

// Node i goes to node-region offset `offset[i]`; the node region spans `node_region_bytes`
// (rounded up to 64). An interior node's word0 is `interior_word0(i)` (word1 its split).
template <class InteriorWord0>
MemoryImage write_8_byte_nodes(const KdTree& tree, const Scene& scene, const std::string& name,
                               uint64_t node_region_bytes, const std::vector<uint64_t>& offset,
                               InteriorWord0 interior_word0) {
  MemoryImage image;
  image.layout = name;
  image.node_bytes = 8;
  image.nodes = {0, align_region(node_region_bytes)};
  std::vector<uint64_t> list_addr;
  write_lists_and_triangles(tree, scene, image.nodes.end_addr(), image, list_addr);
  for (uint32_t i = 0; i < tree.nodes.size(); ++i) {
    const KdNode& n = tree.nodes[i];
    uint32_t w0, w1;
    if (n.is_leaf()) {
      w0 = (n.ref_count << 2) | 3u;
      w1 = leaf_payload_word(tree, i, image, list_addr);
    } else {
      w0 = interior_word0(i);
      std::memcpy(&w1, &n.split, sizeof(float));
    }
    image.store<uint64_t>(image.nodes.base_addr + offset[i], (uint64_t{w1} << 32) | w0);
  }
  image.root_addr = image.nodes.base_addr + offset[0];
  return image;
}

}  // namespace rtusim
