// The layout seam: how a logical kd-tree becomes bytes at addresses. Chosen by `layout.kind`.
#pragma once
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "kdtree/kd_tree.h"
#include "layout/memory_image.h"
#include "scene/scene.h"

namespace rtusim {

class Layout {
 public:
  virtual ~Layout() = default;
  virtual std::string_view name() const = 0;
  // Serialises the tree, its leaf lists and the scene's triangles into one memory image.
  virtual MemoryImage build_image(const KdTree& tree, const Scene& scene) const = 0;
};

// The layout named `kind`; throws InputError listing the known kinds otherwise.
std::unique_ptr<Layout> make_layout(const std::string& kind);
std::vector<std::string> layout_kinds();

class ConfigReader;
// Reads layout.kind (one name or a list; declared in layout.cpp).
std::vector<std::string> read_layout_kinds(ConfigReader& r);

// Writes the lists and triangles regions that every layout shares, starting at `addr`
// (after the nodes), and sizes the image. `leaf_list_addr[i]` receives the list address of
// leaf node i (0 for leaves with fewer than two triangles).
void write_lists_and_triangles(const KdTree& tree, const Scene& scene, uint64_t addr,
                               MemoryImage& image, std::vector<uint64_t>& leaf_list_addr);

// The payload word of leaf `node`, the same in every layout: 0 triangles -> 0, one -> its
// triangle id, two or more -> the index of its first entry in the lists region.
uint32_t leaf_payload_word(const KdTree& tree, uint32_t node, const MemoryImage& image,
                           const std::vector<uint64_t>& leaf_list_addr);

}  // namespace rtusim
