// Ordered depth-first layout: the logical tree in pre-order, larger child first.
#include "layout/odfl_layout.h"

#include "layout/depth_first_writer.h"

namespace rtusim {

MemoryImage OdflLayout::build_image(const KdTree& tree, const Scene& scene) const {
  return write_depth_first(
      tree, scene, kName, uint64_t{1} << 29, above_adjacent,
      [](const KdNode& n, bool flip, uint32_t other_slot) {
        return (other_slot << 3) | (flip ? kReorderBit : 0u) | n.axis;
      });
}

}  // namespace rtusim
