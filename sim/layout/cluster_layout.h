// Probability-guided cluster layout: 8-byte nodes packed eight to a 64-byte block, each block
// the treelet of the nodes a ray that enters it is most likely to visit, the probability
// estimated, as ODFL does for one child, from surface areas.
#pragma once
#include <cstdint>

#include "layout/block_cluster.h"
#include "layout/layout.h"
#include "layout/node_view.h"

namespace rtusim {

// Encoding: layout/block_cluster.h (8-byte nodes, 3-bit in-block child slots, global slots for
// children outside the block); no node straddles a 64-byte block.
// Placement: BlockCluster::pack with priority of node i = the surface area of i's box over the
// root's (the chance that a ray through the scene box visits i; within a block, proportional to
// the chance relative to the block root). Blocks are full but for the rare padding slot, so
// memory is within a few percent of DFL's.
// The decoder, decode(image, addr), is BlockCluster's.
class ClusterLayout final : public Layout, public BlockCluster {
 public:
  static constexpr const char* kName = "cluster";
  std::string_view name() const override { return kName; }
  MemoryImage build_image(const KdTree& tree, const Scene& scene) const override;
};

}  // namespace rtusim
