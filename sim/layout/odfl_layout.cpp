// Ordered depth-first layout: serialises the logical tree in pre-order, larger child first.
#include "layout/odfl_layout.h"

#include <cstring>
#include <string>

#include "util/error.h"

namespace rtusim {

MemoryImage OdflLayout::build_image(const KdTree& tree, const Scene& scene) const {
  MemoryImage image;
  image.layout = "odfl";
  image.node_bytes = kNodeBytes;
  if (tree.nodes.size() >= (1u << 29))
    throw InputError("layout odfl: tree has " + std::to_string(tree.nodes.size()) +
                     " nodes, more than the 29-bit child index holds");

  // Pre-order numbering with the larger child visited first, so it sits after its parent.
  // Each node's box is carried down from the tree bounds to decide which child is larger.
  struct Item {
    uint32_t node;
    Bounds3f box;
  };
  std::vector<uint32_t> order;  // logical node index at each depth-first slot
  order.reserve(tree.nodes.size());
  std::vector<uint8_t> flipped(tree.nodes.size(), 0);  // interior: above child is adjacent
  std::vector<Item> stack{{0, tree.bounds}};
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    order.push_back(it.node);
    const KdNode& n = tree.nodes[it.node];
    if (n.is_leaf()) continue;
    const Item below{n.below, KdTree::below_bounds(n, it.box)};
    const Item above{n.above, KdTree::above_bounds(n, it.box)};
    flipped[it.node] = above_adjacent(n, it.box);
    stack.push_back(flipped[it.node] ? below : above);  // the far child, visited second
    stack.push_back(flipped[it.node] ? above : below);  // the adjacent child, visited next
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
      const bool flip = flipped[order[s]] != 0;
      const uint32_t other = slot_of[flip ? n.below : n.above];
      w0 = (other << 3) | (flip ? kReorderBit : 0u) | n.axis;
      std::memcpy(&w1, &n.split, sizeof(float));
    }
    image.store<uint64_t>(uint64_t{s} * kNodeBytes, (uint64_t{w1} << 32) | w0);
  }
  image.root_addr = 0;
  return image;
}

}  // namespace rtusim
