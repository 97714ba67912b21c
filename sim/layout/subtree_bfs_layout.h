// The subtree layout with its first clustering (`subtree-bfs`): the same 12-byte nodes and
// 64-byte blocks as `subtree`, but every hanging subtree starts a block of its own (top-down,
// breadth first), so small subtrees leave blocks part empty (about 3x DFL's node memory).
// Kept to compare against the full-block `subtree`; decoded by SubtreeLayout::decode.
#pragma once
#include "layout/subtree_layout.h"

namespace rtusim {

class SubtreeBfsLayout final : public SubtreeLayout {
 public:
  static constexpr const char* kName = "subtree-bfs";
  SubtreeBfsLayout() : SubtreeLayout(false) {}
};

}  // namespace rtusim
