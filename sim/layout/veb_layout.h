// Cache-oblivious van Emde Boas layout (after Yoon & Manocha's cache-oblivious layouts of
// hierarchies): the tree is cut at half its height, the top half laid out first, then each
// bottom subtree, each part recursively, so any line or page size holds whole small subtrees.
#pragma once
#include <cstdint>

#include "layout/layout.h"
#include "layout/node_view.h"
#include "layout/pair_node.h"

namespace rtusim {

// Encoding: layout/pair_node.h (8-byte nodes, children side by side in a 16-byte pair unit,
// one 30-bit pair index per interior node); no node straddles a 16-byte line.
// Placement: the units form a binary tree (the unit of interior node i, then the units of i's
// interior children). Of a subtree of height h (in units), the top floor(h/2) levels are laid
// out first, then every subtree hanging below them, below before above, each recursively with
// the heights that remain; unit 0 (the root's) comes first. Memory: DFL's plus 8 bytes, rounded
// up to 64 bytes. No block size enters the placement.
// The decoder, decode(image, addr), is PairNode's.
class VebLayout final : public Layout, public PairNode {
 public:
  static constexpr const char* kName = "veb";
  std::string_view name() const override { return kName; }
  MemoryImage build_image(const KdTree& tree, const Scene& scene) const override;
};

}  // namespace rtusim
