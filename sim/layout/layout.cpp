// Layout factory and the lists/triangles regions every layout shares.
#include "layout/layout.h"

#include "config/param.h"
#include "layout/layouts.h"
#include "util/error.h"

namespace rtusim {

namespace {
const StringListParam kLayoutKind("layout.kind", {"dfl"}, Layouts::names(),
                                  "node layout, or a list of layouts run on the same rays");
}  // namespace

std::vector<std::string> layout_kinds() { return Layouts::names(); }

std::vector<std::string> read_layout_kinds(ConfigReader& r) { return kLayoutKind.read(r); }

std::unique_ptr<Layout> make_layout(const std::string& kind) {
  if (!Layouts::contains(kind))
    throw InputError("layout.kind: unknown layout '" + kind + "' (known: " +
                     Layouts::names_text() + ")");
  return Layouts::dispatch(kind, []<class L>() -> std::unique_ptr<Layout> {
    return std::make_unique<L>();
  });
}

void write_lists_and_triangles(const KdTree& tree, const Scene& scene, uint64_t addr,
                               MemoryImage& image, std::vector<uint64_t>& leaf_list_addr) {
  // Lists region: one u32 triangle id per reference, for leaves with two or more triangles.
  uint64_t list_entries = 0;
  for (const KdNode& n : tree.nodes)
    if (n.is_leaf() && n.ref_count >= 2) list_entries += n.ref_count;
  image.lists = {align_region(addr), list_entries * sizeof(uint32_t)};
  image.triangles = {align_region(image.lists.end_addr()),
                     uint64_t{scene.triangle_count()} * MemoryImage::kTriangleBytes};
  image.bytes.assign(align_region(image.triangles.end_addr()), 0);

  leaf_list_addr.assign(tree.nodes.size(), 0);
  uint64_t cursor = image.lists.base_addr;
  for (size_t i = 0; i < tree.nodes.size(); ++i) {
    const KdNode& n = tree.nodes[i];
    if (!n.is_leaf() || n.ref_count < 2) continue;
    leaf_list_addr[i] = cursor;
    for (uint32_t r = 0; r < n.ref_count; ++r, cursor += sizeof(uint32_t))
      image.store<uint32_t>(cursor, tree.refs[n.first_ref + r]);
  }

  // Triangles region: three float3 vertices per triangle, indexed by triangle id.
  for (uint32_t t = 0; t < scene.triangle_count(); ++t) {
    const auto v = scene.vertices(t);
    float xyz[9] = {v[0].x, v[0].y, v[0].z, v[1].x, v[1].y, v[1].z, v[2].x, v[2].y, v[2].z};
    image.store(image.triangle_addr(t), xyz);
  }
  for (int a = 0; a < 3; ++a) {
    image.bounds_min[a] = tree.bounds.min[a];
    image.bounds_max[a] = tree.bounds.max[a];
  }
}

uint32_t leaf_payload_word(const KdTree& tree, uint32_t node, const MemoryImage& image,
                           const std::vector<uint64_t>& leaf_list_addr) {
  const KdNode& n = tree.nodes[node];
  if (n.ref_count == 0) return 0;
  if (n.ref_count == 1) return tree.refs[n.first_ref];
  return static_cast<uint32_t>((leaf_list_addr[node] - image.lists.base_addr) / sizeof(uint32_t));
}

}  // namespace rtusim
