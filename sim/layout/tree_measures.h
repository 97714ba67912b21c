// Per-node measures of a logical kd-tree that layouts place by.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "kdtree/kd_tree.h"

namespace rtusim {

// Surface area of every node's box, from the tree's bounds down.
inline std::vector<double> node_surface_areas(const KdTree& tree) {
  std::vector<double> area(tree.nodes.size(), 0.0);
  std::vector<std::pair<uint32_t, Bounds3f>> stack{{0u, tree.bounds}};
  while (!stack.empty()) {
    const auto [i, box] = stack.back();
    stack.pop_back();
    area[i] = box.surface_area();
    const KdNode& n = tree.nodes[i];
    if (n.is_leaf()) continue;
    stack.push_back({n.below, KdTree::below_bounds(n, box)});
    stack.push_back({n.above, KdTree::above_bounds(n, box)});
  }
  return area;
}

// Every node's surface area over the root's (the probability that a ray through the root box
// also crosses the node's box, as ODFL orders children); 1 for a flat root.
inline std::vector<double> node_area_probabilities(const KdTree& tree) {
  std::vector<double> p = node_surface_areas(tree);
  const double root_area = p[0] > 0.0 ? p[0] : 1.0;
  for (double& v : p) v /= root_area;
  return p;
}

// Number of nodes in every node's subtree (itself included).
inline std::vector<uint32_t> subtree_node_counts(const KdTree& tree) {
  std::vector<uint32_t> count(tree.nodes.size(), 1), preorder{0};
  preorder.reserve(tree.nodes.size());
  for (size_t k = 0; k < preorder.size(); ++k) {
    const KdNode& n = tree.nodes[preorder[k]];
    if (!n.is_leaf()) preorder.insert(preorder.end(), {n.below, n.above});
  }
  for (auto it = preorder.rbegin(); it != preorder.rend(); ++it) {
    const KdNode& n = tree.nodes[*it];
    if (!n.is_leaf()) count[*it] += count[n.below] + count[n.above];
  }
  return count;
}

}  // namespace rtusim
