// Depth-first layout: serialises the logical tree in pre-order, below child first.
#include "layout/dfl_layout.h"

#include <cstring>

#include "util/error.h"

namespace rtusim {

MemoryImage DflLayout::build_image(const KdTree& tree, const Scene& scene) const {
  MemoryImage image;
  image.layout = "dfl";
  image.node_bytes = kNodeBytes;
  if (tree.nodes.size() >= (1u << 30))
    throw InputError("layout dfl: tree has " + std::to_string(tree.nodes.size()) +
                     " nodes, more than the 30-bit child index holds");

  // Pre-order numbering: below subtree first, so the below child sits after its parent.
  std::vector<uint32_t> order;  // logical node index at each depth-first slot
  order.reserve(tree.nodes.size());
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    const uint32_t n = stack.back();
    stack.pop_back();
    order.push_back(n);
    if (!tree.nodes[n].is_leaf()) {
      stack.push_back(tree.nodes[n].above);
      stack.push_back(tree.nodes[n].below);
    }
  }
  std::vector<uint32_t> slot_of(tree.nodes.size());
  for (uint32_t s = 0; s < order.size(); ++s) slot_of[order[s]] = s;

  image.nodes = {0, uint64_t{order.size()} * kNodeBytes};
  std::vector<uint64_t> list_addr;
  write_lists_and_triangles(tree, scene, image.nodes.end_addr(), image, list_addr);

  // Node words.
  for (uint32_t s = 0; s < order.size(); ++s) {
    const KdNode& n = tree.nodes[order[s]];
    uint32_t w0, w1;
    if (n.is_leaf()) {
      w0 = (n.ref_count << 2) | 3u;
      w1 = leaf_payload_word(tree, order[s], image, list_addr);
    } else {
      w0 = (slot_of[n.above] << 2) | n.axis;
      std::memcpy(&w1, &n.split, sizeof(float));
    }
    image.store<uint64_t>(uint64_t{s} * kNodeBytes, (uint64_t{w1} << 32) | w0);
  }
  image.root_addr = 0;
  return image;
}

}  // namespace rtusim
