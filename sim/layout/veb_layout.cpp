// Van Emde Boas layout: recursive half-height cuts of the tree of pair units.
#include "layout/veb_layout.h"

#include <algorithm>

namespace rtusim {
namespace {

// Lays out the units of the tree of interior nodes in van Emde Boas order.
class VebOrder {
 public:
  explicit VebOrder(const KdTree& tree) : tree_(tree), unit_of_(tree.nodes.size(), 0) {}

  std::vector<uint32_t> run(uint64_t& units) {
    if (!tree_.nodes[0].is_leaf()) place(0, height(0));
    units = next_;
    return std::move(unit_of_);
  }

 private:
  bool interior(uint32_t i) const { return !tree_.nodes[i].is_leaf(); }

  // Height in units of the subtree of interior node `root` (1 = no interior children).
  uint32_t height(uint32_t root) const {
    uint32_t h = 0;
    std::vector<std::pair<uint32_t, uint32_t>> stack{{root, 1u}};
    while (!stack.empty()) {
      const auto [i, d] = stack.back();
      stack.pop_back();
      h = std::max(h, d);
      for (const uint32_t c : {tree_.nodes[i].above, tree_.nodes[i].below})
        if (interior(c)) stack.push_back({c, d + 1});
    }
    return h;
  }

  // Places the units of `root`'s subtree within `h` levels of it.
  void place(uint32_t root, uint32_t h) {
    if (h == 1) {
      unit_of_[root] = static_cast<uint32_t>(next_++);
      return;
    }
    const uint32_t top = h / 2;
    place(root, top);
    std::vector<uint32_t> frontier;  // interior nodes `top` levels below root, below first
    std::vector<std::pair<uint32_t, uint32_t>> stack{{root, 0u}};
    while (!stack.empty()) {
      const auto [i, d] = stack.back();
      stack.pop_back();
      if (d == top) {
        frontier.push_back(i);
        continue;
      }
      for (const uint32_t c : {tree_.nodes[i].above, tree_.nodes[i].below})
        if (interior(c)) stack.push_back({c, d + 1});
    }
    for (const uint32_t f : frontier) place(f, h - top);
  }

  const KdTree& tree_;
  std::vector<uint32_t> unit_of_;
  uint64_t next_ = 1;
};

}  // namespace

MemoryImage VebLayout::build_image(const KdTree& tree, const Scene& scene) const {
  uint64_t units = 0;
  const std::vector<uint32_t> unit_of = VebOrder(tree).run(units);
  return write_pair_image(tree, scene, kName, unit_of, units);
}

}  // namespace rtusim
