// Probability-guided cluster layout: surface-area priorities into the greedy block packer.
#include "layout/cluster_layout.h"

#include "layout/tree_measures.h"

namespace rtusim {

MemoryImage ClusterLayout::build_image(const KdTree& tree, const Scene& scene) const {
  const std::vector<double> priority = node_area_probabilities(tree);
  uint64_t slots = 0;
  const std::vector<uint32_t> slot_of = BlockCluster::pack(tree, priority, slots);
  return BlockCluster::write(tree, scene, kName, slot_of, slots);
}

}  // namespace rtusim
