// O(N log N) SAH kd-tree builder (Wald & Havran 2006): split events sorted once and kept sorted
// down the tree, perfect splits (triangles clipped to the node box), deterministic.
#pragma once
#include "kdtree/kd_tree.h"
#include "scene/scene.h"

namespace rtusim {

// Builds the tree over every triangle of `scene`. Deterministic: the same scene and params give
// the same tree. Fills KdTree::report (build_seconds included).
KdTree build_sah_kd_tree(const Scene& scene, const KdBuildParams& params);

}  // namespace rtusim
