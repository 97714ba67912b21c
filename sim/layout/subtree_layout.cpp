// Ordinary subtree layout: clusters the logical tree top-down into five-node blocks, full
// ones (subtree) or one subtree per block (subtree-bfs).
#include "layout/subtree_layout.h"

#include <cstring>
#include <deque>
#include <string>

#include "util/error.h"

namespace rtusim {

MemoryImage SubtreeLayout::build_image(const KdTree& tree, const Scene& scene) const {
  MemoryImage image;
  image.layout = std::string(name());
  image.node_bytes = kNodeBytes;

  // Clustering: pop a block root, fill its block breadth-first, push what hangs below.
  std::vector<uint32_t> ref_of(tree.nodes.size());
  std::vector<uint32_t> roots{0};  // block roots still to place, next on top
  std::deque<uint32_t> fill;
  uint64_t blocks = 0;
  while (!roots.empty()) {
    fill.assign(1, roots.back());
    roots.pop_back();
    for (uint32_t slot = 0; slot < kNodesPerBlock; ++slot) {
      // Shared blocks: a block whose subtree runs out goes on with the next pending root.
      if (fill.empty() && shared_blocks_ && !roots.empty()) {
        fill.push_back(roots.back());
        roots.pop_back();
      }
      if (fill.empty()) break;
      const uint32_t n = fill.front();
      fill.pop_front();
      ref_of[n] = static_cast<uint32_t>(blocks << kSlotBits) | slot;
      if (!tree.nodes[n].is_leaf()) {
        fill.push_back(tree.nodes[n].below);
        fill.push_back(tree.nodes[n].above);
      }
    }
    // Hanging nodes become the next blocks, the first of them placed first (depth first).
    roots.insert(roots.end(), fill.rbegin(), fill.rend());
    if (++blocks > (1u << (32 - 2 - kSlotBits)))
      throw InputError("layout " + std::string(name()) + ": tree has " + std::to_string(tree.nodes.size()) +
                       " nodes, more blocks than the 27-bit block index holds");
  }

  image.nodes = {0, blocks * kBlockBytes};
  std::vector<uint64_t> list_addr;
  write_lists_and_triangles(tree, scene, image.nodes.end_addr(), image, list_addr);

  // Node words.
  for (uint32_t i = 0; i < tree.nodes.size(); ++i) {
    const KdNode& n = tree.nodes[i];
    uint32_t w[3];
    if (n.is_leaf()) {
      w[0] = (n.ref_count << 2) | 3u;
      w[1] = leaf_payload_word(tree, i, image, list_addr);
      w[2] = 0;
    } else {
      w[0] = (ref_of[n.below] << 2) | n.axis;
      std::memcpy(&w[1], &n.split, sizeof(float));
      w[2] = ref_of[n.above];
    }
    image.store(image.nodes.base_addr + ref_offset(ref_of[i]), w);
  }
  image.root_addr = image.nodes.base_addr + ref_offset(ref_of[0]);
  return image;
}

}  // namespace rtusim
