// The SAH builder's keys (kdtree.*): cost model and limits.
#include "config/param.h"
#include "kdtree/sah_builder.h"

namespace rtusim {
namespace {

const KdBuildParams kDefaults;
const FloatParam kTraversalCost("kdtree.traversal_cost", kDefaults.traversal_cost, 1e-6, 1e6, "",
                                "SAH cost of one traversal step");
const FloatParam kIsectCost("kdtree.isect_cost", kDefaults.isect_cost, 1e-6, 1e6, "",
                            "SAH cost of one ray-triangle test");
const FloatParam kEmptyBonus("kdtree.empty_bonus", kDefaults.empty_bonus, 0.0, 0.99, "",
                             "cost discount for splits that cut off empty space");
const IntParam kMaxDepth("kdtree.max_depth", kDefaults.max_depth, -1, KdBuildParams::kMaxDepthLimit,
                         "levels",
                         "depth limit; -1: round(8 + 1.3 log2 N)");
const IntParam kLeafPrims("kdtree.leaf_prims", kDefaults.leaf_prims, 1, 1 << 20, "triangles",
                          "make a leaf at or below this many triangles");

}  // namespace

KdBuildParams read_kd_build_params(ConfigReader& r) {
  KdBuildParams p;
  p.traversal_cost = static_cast<float>(kTraversalCost.read(r));
  p.isect_cost = static_cast<float>(kIsectCost.read(r));
  p.empty_bonus = static_cast<float>(kEmptyBonus.read(r));
  p.max_depth = static_cast<int>(kMaxDepth.read(r));
  p.leaf_prims = static_cast<int>(kLeafPrims.read(r));
  return p;
}

}  // namespace rtusim
