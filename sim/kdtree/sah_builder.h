// O(N log N) SAH kd-tree builder (Wald & Havran 2006): split events sorted once and kept sorted
// down the tree, perfect splits (triangles clipped to the node box), deterministic.
#pragma once
#include "kdtree/kd_tree.h"
#include "scene/scene.h"

namespace rtusim {

// Builds the tree over every triangle of `scene`. Deterministic: the same scene and params give
// the same tree. Fills KdTree::report (build_seconds included).
KdTree build_sah_kd_tree(const Scene& scene, const KdBuildParams& params);

// Depth limit the builder applies: params.max_depth, or round(8 + 1.3 log2 N) when it is -1
// (8 for an empty scene). The root has depth 0; no node is deeper than this.
int kd_max_depth(uint64_t triangle_count, const KdBuildParams& params);

class ConfigReader;
// Reads the kdtree.* keys (declared in kd_build_params.cpp).
KdBuildParams read_kd_build_params(ConfigReader& r);

}  // namespace rtusim
