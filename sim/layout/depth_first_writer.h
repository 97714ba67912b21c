// What DFL and ODFL share: 8-byte nodes in pre-order with one child stored right after its
// parent and a pointer to the other, and the same leaf words. The two differ only in which child
// is adjacent and in how an interior node's first word says so.
#pragma once
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "layout/layout.h"
#include "layout/node_view.h"
#include "util/error.h"

namespace rtusim {

// Serialises `tree` as `name`. `above_adjacent(node, box)` picks the child stored next to an
// interior node; `interior_word0(node, above_adjacent, other_slot)` encodes its first word
// (word1 is the split). `max_nodes` is what the child index field holds.
template <class AboveAdjacent, class InteriorWord0>
MemoryImage write_depth_first(const KdTree& tree, const Scene& scene, const std::string& name,
                              uint64_t max_nodes, AboveAdjacent above_adjacent,
                              InteriorWord0 interior_word0) {
  constexpr uint32_t kNodeBytes = 8;
  MemoryImage image;
  image.layout = name;
  image.node_bytes = kNodeBytes;
  if (tree.nodes.size() >= max_nodes)
    throw InputError("layout " + name + ": tree has " + std::to_string(tree.nodes.size()) +
                     " nodes, more than its child index holds");

  // Pre-order numbering, the adjacent child visited first; boxes carried down from the root.
  struct Item {
    uint32_t node;
    Bounds3f box;
  };
  std::vector<uint32_t> order;  // logical node index at each depth-first slot
  order.reserve(tree.nodes.size());
  std::vector<uint8_t> flipped(tree.nodes.size(), 0);  // interior: the above child is adjacent
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
    stack.push_back(flipped[it.node] ? below : above);  // the other child, visited second
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
      w0 = interior_word0(n, flip, slot_of[flip ? n.below : n.above]);
      std::memcpy(&w1, &n.split, sizeof(float));
    }
    image.store<uint64_t>(uint64_t{s} * kNodeBytes, (uint64_t{w1} << 32) | w0);
  }
  image.root_addr = 0;
  return image;
}

// Decodes the first 8 bytes of a depth-first node into `v`: axis and leaf fields; true for a
// leaf (the caller decodes an interior node's children).
inline bool decode_depth_first_common(const MemoryImage& image, uint64_t addr, NodeView& v,
                                      uint32_t& w0) {
  const uint64_t raw = image.load<uint64_t>(addr);
  w0 = static_cast<uint32_t>(raw);
  const uint32_t w1 = static_cast<uint32_t>(raw >> 32);
  v.axis = w0 & 3u;
  v.leaf = v.axis == 3u;
  if (v.leaf) {
    v.prim_count = w0 >> 2;
    v.inline_prim = w1;
    v.list_addr = image.lists.base_addr + uint64_t{w1} * sizeof(uint32_t);
  } else {
    std::memcpy(&v.split, &w1, sizeof(float));
  }
  return v.leaf;
}

}  // namespace rtusim
