// The logical kd-tree: what the SAH builder produces and what every layout serialises.
#pragma once
#include <cstdint>
#include <vector>

#include "geom/bounds.h"

namespace rtusim {

// Cost model and limits of the SAH build (pbrt's defaults).
struct KdBuildParams {
  static constexpr int kMaxDepthLimit = 60;  // the deepest tree max_depth may ask for
  float traversal_cost = 1.0f;
  float isect_cost = 80.0f;
  float empty_bonus = 0.5f;  // in [0, 1): cost discount for splits that cut off empty space
  int max_depth = -1;        // -1: 8 + 1.3 log2(N), rounded (at most kMaxDepthLimit)
  int leaf_prims = 1;        // make a leaf when at most this many triangles remain
};

// One node of the logical tree. Children are indices into KdTree::nodes.
struct KdNode {
  static constexpr uint8_t kLeaf = 3;
  uint8_t axis = kLeaf;  // 0, 1, 2 = split axis of an interior node; kLeaf = leaf
  float split = 0.0f;    // interior: split plane position on `axis`
  uint32_t below = 0;    // interior: child on the low side of the plane
  uint32_t above = 0;    // interior: child on the high side of the plane
  uint32_t first_ref = 0;  // leaf: first entry in KdTree::refs
  uint32_t ref_count = 0;  // leaf: number of triangles in the leaf
  bool is_leaf() const { return axis == kLeaf; }
};

// The tree report that goes into the stats.
struct KdTreeReport {
  uint64_t nodes = 0, leaves = 0, empty_leaves = 0;
  uint32_t max_depth = 0;
  double mean_leaf_depth = 0.0;     // over non-empty leaves
  double refs_per_triangle = 0.0;   // references in leaves / triangles
  double sah_cost = 0.0;            // expected cost of a random ray, SAH model
  double build_seconds = 0.0;
  uint64_t peak_build_bytes = 0;    // builder's largest working set, estimated
};

struct KdTree {
  std::vector<KdNode> nodes;    // nodes[0] is the root
  std::vector<uint32_t> refs;   // leaf triangle lists, each leaf a contiguous run
  Bounds3f bounds;              // scene bounds the tree subdivides
  KdTreeReport report;

  // Bounds of the two children of interior node `n` whose own bounds are `b`.
  static Bounds3f below_bounds(const KdNode& n, Bounds3f b) { b.max[n.axis] = n.split; return b; }
  static Bounds3f above_bounds(const KdNode& n, Bounds3f b) { b.min[n.axis] = n.split; return b; }
};

}  // namespace rtusim
