// Ordinary subtree layout: clusters the logical tree top-down into five-node blocks, full
// ones (subtree) or one subtree per block (subtree-bfs).
#include "layout/subtree_layout.h"

#include <cstring>
#include <deque>
#include <string>

#include "layout/subtree_bfs_layout.h"
#include "layout/tree_measures.h"
#include "util/error.h"

namespace rtusim {

std::string_view SubtreeLayout::name() const {
  return shared_blocks_ ? kName : SubtreeBfsLayout::kName;
}

MemoryImage SubtreeLayout::build_image(const KdTree& tree, const Scene& scene) const {
  MemoryImage image;
  image.layout = std::string(name());
  image.node_bytes = kNodeBytes;

  const std::vector<uint32_t> size = subtree_node_counts(tree);

  // Clustering: pop a block root, fill its block breadth-first, push what hangs below.
  std::vector<uint32_t> ref_of(tree.nodes.size());
  std::vector<uint32_t> roots{0};  // block roots still to place, next on top
  std::deque<uint32_t> fill;
  uint64_t blocks = 0;
  const auto new_block = [&] {
    if (blocks >= (uint64_t{1} << (32 - 2 - kSlotBits)))
      throw InputError("layout " + std::string(name()) + ": tree has " +
                       std::to_string(tree.nodes.size()) +
                       " nodes, more blocks than the 27-bit block index holds");
    return blocks++;
  };
  // Fills `block` breadth-first from `fill`, from `slot` on; returns the next free slot.
  const auto fill_block = [&](uint64_t block, uint32_t slot) {
    for (; slot < kNodesPerBlock && !fill.empty(); ++slot) {
      const uint32_t n = fill.front();
      fill.pop_front();
      ref_of[n] = static_cast<uint32_t>(block << kSlotBits) | slot;
      if (!tree.nodes[n].is_leaf()) {
        fill.push_back(tree.nodes[n].below);
        fill.push_back(tree.nodes[n].above);
      }
    }
    return slot;
  };
  // Shared blocks with free slots, most recently opened last.
  struct Shared {
    uint64_t block;
    uint32_t used;
  };
  std::vector<Shared> shared;
  const auto place_small = [&](uint32_t root) {
    size_t k = shared.size();
    const size_t stop = shared.size() > kSharedSearch ? shared.size() - kSharedSearch : 0;
    while (k > stop && shared[k - 1].used + size[root] > kNodesPerBlock) --k;
    if (k == stop) {
      shared.push_back({new_block(), 0});
      k = shared.size();
    }
    Shared& b = shared[k - 1];
    fill.assign(1, root);
    b.used = fill_block(b.block, b.used);
    if (b.used == kNodesPerBlock) shared.erase(shared.begin() + static_cast<std::ptrdiff_t>(k - 1));
  };
  std::vector<uint32_t> hanging;
  while (!roots.empty()) {
    fill.assign(1, roots.back());
    roots.pop_back();
    fill_block(new_block(), 0);
    // Hanging nodes become the next blocks, the first of them placed first (depth first);
    // with shared blocks, subtrees smaller than a block go whole into a shared block.
    hanging.assign(fill.begin(), fill.end());
    fill.clear();
    for (auto it = hanging.rbegin(); it != hanging.rend(); ++it)
      if (!shared_blocks_ || size[*it] >= kNodesPerBlock) roots.push_back(*it);
    if (shared_blocks_)
      for (const uint32_t h : hanging)
        if (size[h] < kNodesPerBlock) place_small(h);
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
