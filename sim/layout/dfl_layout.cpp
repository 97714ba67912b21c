// Depth-first layout: the logical tree in pre-order, below child first.
#include "layout/dfl_layout.h"

#include "layout/depth_first_writer.h"

namespace rtusim {

MemoryImage DflLayout::build_image(const KdTree& tree, const Scene& scene) const {
  return write_depth_first(
      tree, scene, kName, uint64_t{1} << 30, [](const KdNode&, const Bounds3f&) { return false; },
      [](const KdNode& n, bool, uint32_t above_slot) { return (above_slot << 2) | n.axis; });
}

}  // namespace rtusim
