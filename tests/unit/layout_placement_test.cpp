// The layouts beyond the study (veb, cluster, profile): the placement each promises, the
// profile's determinism, and, on the shared scenes, the same hits and the same logical node
// visits as DFL for every layout.
#include <gtest/gtest.h>

#include "../skip_unless_ci.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <random>
#include <set>

#include <glm/geometric.hpp>

#include "app/profile_training.h"
#include "kdtree/sah_builder.h"
#include "layout/block_cluster.h"
#include "layout/cluster_layout.h"
#include "layout/layout.h"
#include "layout/layout_dispatch.h"
#include "layout/pair_node.h"
#include "layout/tree_measures.h"
#include "layout/profile_layout.h"
#include "layout/veb_layout.h"
#include "median_kd_tree.h"
#include "scene/gltf_loader.h"
#include "scene/pinhole_camera.h"
#include "traversal/traversal.h"

namespace rtusim {
namespace {

// Address of every logical node, walking the image from its root beside the tree; checks
// that every node decodes to its logical node's fields.
std::vector<uint64_t> addresses(const MemoryImage& image, const KdTree& tree) {
  std::vector<uint64_t> addr_of(tree.nodes.size(), ~uint64_t{0});
  std::vector<std::pair<uint32_t, uint64_t>> stack{{0u, image.root_addr}};
  while (!stack.empty()) {
    const auto [i, addr] = stack.back();
    stack.pop_back();
    addr_of[i] = addr;
    const uint64_t at = addr;  // a structured binding cannot be captured (C++20 as clang reads it)
    const NodeView v = with_layout_decoder(image, [&]<class D>() { return D::decode(image, at); });
    const KdNode& n = tree.nodes[i];
    EXPECT_EQ(v.leaf, n.is_leaf()) << image.layout << " node " << i;
    if (v.leaf != n.is_leaf()) continue;
    if (n.is_leaf()) {
      EXPECT_EQ(v.prim_count, n.ref_count) << image.layout << " node " << i;
      continue;
    }
    EXPECT_EQ(v.axis, n.axis);
    EXPECT_EQ(std::memcmp(&v.split, &n.split, sizeof(float)), 0);
    stack.push_back({n.below, v.below_addr});
    stack.push_back({n.above, v.above_addr});
  }
  EXPECT_EQ(std::set<uint64_t>(addr_of.begin(), addr_of.end()).size(), tree.nodes.size())
      << image.layout << ": two nodes at one address";
  return addr_of;
}

constexpr auto soup = testing::soup_tree;

uint64_t interior_count(const KdTree& tree) {
  uint64_t n = 0;
  for (const KdNode& k : tree.nodes) n += !k.is_leaf();
  return n;
}

std::vector<uint32_t> depths(const KdTree& tree) {
  std::vector<uint32_t> d(tree.nodes.size(), 0);
  std::vector<uint32_t> order{0};
  for (size_t k = 0; k < order.size(); ++k) {
    const KdNode& n = tree.nodes[order[k]];
    if (n.is_leaf()) continue;
    d[n.below] = d[n.above] = d[order[k]] + 1;
    order.insert(order.end(), {n.below, n.above});
  }
  return d;
}

TEST(VebLayout, SiblingsShareAUnitAndTheTopHalfComesFirst) {
  const testing::SoupTree f = soup(3000, 2, 51);
  const MemoryImage image = VebLayout().build_image(f.tree, f.scene);
  const std::vector<uint64_t> addr_of = addresses(image, f.tree);
  EXPECT_EQ(image.root_addr, image.nodes.base_addr);
  EXPECT_EQ(image.nodes.size_bytes, align_region((interior_count(f.tree) + 1) * 16));
  const std::vector<uint32_t> depth = depths(f.tree);
  uint32_t height = 0;  // of the tree of pair units: interior nodes' depths
  for (uint32_t i = 0; i < f.tree.nodes.size(); ++i)
    if (!f.tree.nodes[i].is_leaf()) height = std::max(height, depth[i] + 1);
  ASSERT_GE(height, 4u);
  // Units of the top floor(h/2) levels of interior nodes come before every other unit.
  uint64_t last_top = 0, first_bottom = ~uint64_t{0};
  for (uint32_t i = 0; i < f.tree.nodes.size(); ++i) {
    const KdNode& n = f.tree.nodes[i];
    if (n.is_leaf()) continue;
    const uint64_t unit = (addr_of[n.below] - image.nodes.base_addr) / 16;
    EXPECT_EQ(addr_of[n.below] % 16, 0u) << "node " << i;
    EXPECT_EQ(addr_of[n.above], addr_of[n.below] + 8) << "node " << i;
    if (depth[i] < height / 2) last_top = std::max(last_top, unit);
    else first_bottom = std::min(first_bottom, unit);
  }
  EXPECT_LT(last_top, first_bottom);
}

// The placement rule itself, unit by unit, from a recursive reading of veb_layout.h written
// here: a subtree of height h (in units) places its top floor(h/2) levels, then each subtree
// hanging below them, left to right with below before above, with the heights that remain.
// The unit of interior node i is the 16-byte pair of its children (unit 0 holds the root).
std::vector<uint32_t> veb_units(const KdTree& tree) {
  std::vector<uint32_t> unit(tree.nodes.size(), 0);
  uint32_t next = 1;
  const auto interior = [&](uint32_t i) { return !tree.nodes[i].is_leaf(); };
  std::function<uint32_t(uint32_t)> height = [&](uint32_t i) -> uint32_t {
    const KdNode& n = tree.nodes[i];
    uint32_t h = 0;
    for (const uint32_t c : {n.below, n.above})
      if (interior(c)) h = std::max(h, height(c));
    return h + 1;
  };
  // The interior nodes `depth` levels below i, below before above.
  std::function<void(uint32_t, uint32_t, std::vector<uint32_t>&)> level =
      [&](uint32_t i, uint32_t depth, std::vector<uint32_t>& out) {
        if (depth == 0) return out.push_back(i);
        for (const uint32_t c : {tree.nodes[i].below, tree.nodes[i].above})
          if (interior(c)) level(c, depth - 1, out);
      };
  std::function<void(uint32_t, uint32_t)> place = [&](uint32_t root, uint32_t h) {
    if (h == 1) {
      unit[root] = next++;
      return;
    }
    place(root, h / 2);
    std::vector<uint32_t> bottom;
    level(root, h / 2, bottom);
    for (const uint32_t b : bottom) place(b, h - h / 2);
  };
  if (interior(0)) place(0, height(0));
  return unit;
}

TEST(VebLayout, EveryUnitWhereTheRecursiveRulePutsIt) {
  for (const uint32_t seed : {51u, 7u}) {
    const testing::SoupTree f = soup(3000, 2, seed);
    const MemoryImage image = VebLayout().build_image(f.tree, f.scene);
    const std::vector<uint64_t> addr_of = addresses(image, f.tree);
    const std::vector<uint32_t> want = veb_units(f.tree);
    int mismatches = 0;
    for (uint32_t i = 0; i < f.tree.nodes.size(); ++i) {
      if (f.tree.nodes[i].is_leaf()) continue;
      const uint64_t unit = (addr_of[f.tree.nodes[i].below] - image.nodes.base_addr) / 16;
      mismatches += unit != want[i];
      if (mismatches <= 3) EXPECT_EQ(unit, want[i]) << "seed " << seed << " node " << i;
    }
    EXPECT_EQ(mismatches, 0) << "seed " << seed;
  }
}

TEST(ClusterLayout, NodesStayInBlocksBlocksAreFullAndTheFirstIsTheGreedyTreelet) {
  for (uint32_t seed : {52u, 53u}) {
    const testing::SoupTree f = soup(3000, seed == 52u ? 1u : 3u, seed);
    const MemoryImage image = ClusterLayout().build_image(f.tree, f.scene);
    const std::vector<uint64_t> addr_of = addresses(image, f.tree);
    // 8-byte nodes at 8-byte offsets: none straddles a 64-byte block; almost no padding.
    for (const uint64_t a : addr_of) EXPECT_EQ((a - image.nodes.base_addr) % 8, 0u);
    EXPECT_LE(image.nodes.size_bytes, f.tree.nodes.size() * 8 * 102 / 100 + 64);

    // Every child-reference mode occurs.
    std::set<uint32_t> modes;
    for (uint32_t i = 0; i < f.tree.nodes.size(); ++i)
      if (!f.tree.nodes[i].is_leaf()) modes.insert((image.load<uint32_t>(addr_of[i]) >> 2) & 3u);
    EXPECT_EQ(modes.size(), 4u);

    // Block 0: the root, then seven times the most probable (largest box) child of a node
    // already taken, re-derived here.
    std::vector<double> area = node_surface_areas(f.tree);
    std::set<uint32_t> taken{0}, frontier;
    auto open = [&](uint32_t i) {
      if (!f.tree.nodes[i].is_leaf()) frontier.insert({f.tree.nodes[i].below, f.tree.nodes[i].above});
    };
    open(0);
    while (taken.size() < 8 && !frontier.empty()) {
      const uint32_t best = *std::max_element(frontier.begin(), frontier.end(), [&](uint32_t a, uint32_t b) {
        return area[a] != area[b] ? area[a] < area[b] : a > b;
      });
      frontier.erase(best);
      taken.insert(best);
      open(best);
    }
    std::set<uint32_t> block0;
    for (uint32_t i = 0; i < f.tree.nodes.size(); ++i)
      if (addr_of[i] - image.nodes.base_addr < 64) block0.insert(i);
    EXPECT_EQ(block0, taken) << "seed " << seed;
  }
}

TEST(ProfileLayout, DeterministicAndDrivenByItsCounts) {
  const testing::SoupTree f = soup(3000, 2, 54);
  // Counts that favour the above children: the root's block follows the above spine.
  std::vector<uint64_t> visits(f.tree.nodes.size(), 0);
  std::vector<uint32_t> spine{0};
  while (!f.tree.nodes[spine.back()].is_leaf() && spine.size() < 8)
    spine.push_back(f.tree.nodes[spine.back()].above);
  ASSERT_EQ(spine.size(), 8u);
  for (const uint32_t i : spine) visits[i] = 1000;
  const MemoryImage a = ProfileLayout(visits).build_image(f.tree, f.scene);
  const MemoryImage b = ProfileLayout(visits).build_image(f.tree, f.scene);
  EXPECT_EQ(a.bytes, b.bytes);
  const std::vector<uint64_t> addr_of = addresses(a, f.tree);
  for (const uint32_t i : spine) EXPECT_LT(addr_of[i] - a.nodes.base_addr, 64u) << "node " << i;
  // Without counts it is the surface-area cluster layout; with them it is not.
  const MemoryImage plain = ProfileLayout().build_image(f.tree, f.scene);
  const MemoryImage cluster = ClusterLayout().build_image(f.tree, f.scene);
  EXPECT_TRUE(std::equal(plain.bytes.begin(), plain.bytes.begin() + plain.nodes.size_bytes,
                         cluster.bytes.begin()));
  EXPECT_NE(a.bytes, plain.bytes);
}

TEST(ProfileLayout, TrainingIsDeterministicAndUsesAnotherCamera) {
  const testing::SoupTree f = soup(2000, 2, 55);
  CameraDesc cam;
  cam.eye = {0.5f, 0.5f, 3.0f};
  cam.target = {0.5f, 0.5f, 0.5f};
  const CameraDesc train = ProfileLayout::training_camera(cam, f.tree.bounds);
  EXPECT_GT(glm::length(train.eye - cam.eye), 0.1f);
  // Turned around the target (1 unit ahead; the soup's centre is farther): same distance to
  // it, the view turned by the training angle.
  EXPECT_NEAR(glm::length(train.eye - cam.target), glm::length(cam.eye - cam.target), 1e-4f);
  EXPECT_NEAR(glm::degrees(std::acos(glm::dot(glm::normalize(train.target - train.eye),
                                              glm::normalize(cam.target - cam.eye)))),
              ProfileLayout::kTrainingTurnDeg, 1e-2f);
  // A target far beyond the scene: the pivot is at the scene's depth, so the turned camera
  // still looks at the scene.
  CameraDesc far = cam;
  far.target = {0.5f, 0.5f, -20.0f};
  const CameraDesc far_train = ProfileLayout::training_camera(far, f.tree.bounds);
  const glm::vec3 centre = 0.5f * (glm::vec3(f.tree.bounds.min[0], f.tree.bounds.min[1], f.tree.bounds.min[2]) +
                                   glm::vec3(f.tree.bounds.max[0], f.tree.bounds.max[1], f.tree.bounds.max[2]));
  const glm::vec3 to_centre = glm::normalize(centre - far_train.eye);
  EXPECT_GT(glm::dot(to_centre, glm::normalize(far_train.target - far_train.eye)), 0.999f);
  ProfileLayout p1, p2;
  p1.set_visits(profile_training_visits(f.tree, f.scene, cam, TracerParams{}));
  p2.set_visits(profile_training_visits(f.tree, f.scene, cam, TracerParams{}));
  EXPECT_EQ(p1.visits(), p2.visits());
  EXPECT_GT(p1.visits()[0], 0u) << "the root was visited";
  EXPECT_EQ(p1.build_image(f.tree, f.scene).bytes, p2.build_image(f.tree, f.scene).bytes);
  // A child is visited only after its parent: never more often.
  for (uint32_t i = 0; i < f.tree.nodes.size(); ++i) {
    const KdNode& n = f.tree.nodes[i];
    if (n.is_leaf()) continue;
    EXPECT_LE(p1.visits()[n.below], p1.visits()[i]);
    EXPECT_LE(p1.visits()[n.above], p1.visits()[i]);
  }
}

// Logical node visits of one traversal.
struct VisitSink {
  const std::map<uint64_t, uint32_t>* node_at;
  std::vector<uint32_t> visits;
  bool stray = false;
  void fetch(Stream s, uint64_t addr, uint32_t) {
    if (s != Stream::kNode) return;
    const auto it = node_at->find(addr);
    if (it == node_at->end()) stray = true;
    else visits.push_back(it->second);
  }
};

// The shared scenes: camera rays plus random rays, every layout against DFL.
TEST(LayoutsOnSharedScenes, SameHitsAndVisitsAsDfl) {
  namespace fs = std::filesystem;
  const std::string dir = RTUSIM_SCENES_DEFAULT;
  if (!fs::is_directory(dir)) RTUSIM_SKIP_UNLESS_CI("no scenes folder " + dir);
  for (const std::string name : {"box", "cornell_whitted"}) {
    SCOPED_TRACE(name);
    const Scene scene = load_gltf(dir + "/" + name + "/" + name + ".gltf");
    const KdTree tree = build_sah_kd_tree(scene, KdBuildParams{});
    std::vector<MemoryImage> images;
    std::vector<std::map<uint64_t, uint32_t>> node_at;
    for (const std::string& kind : layout_kinds()) {
      const std::unique_ptr<Layout> layout = make_layout(kind);
      if (auto* p = dynamic_cast<ProfileLayout*>(layout.get()))
        p->set_visits(profile_training_visits(tree, scene, scene.cameras.front(), TracerParams{}));
      images.push_back(layout->build_image(tree, scene));
      node_at.emplace_back();
      const std::vector<uint64_t> addr_of = addresses(images.back(), tree);
      for (uint32_t i = 0; i < addr_of.size(); ++i) node_at.back()[addr_of[i]] = i;
    }
    ASSERT_EQ(images.front().layout, "dfl");
    // Rays: a 24x24 camera grid, and random rays from inside the scene box.
    std::vector<Ray> rays;
    const PinholeCamera cam(scene.cameras.front(), 24, 24);
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 24; ++x) rays.push_back(cam.generate(x, y));
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::normal_distribution<float> g;
    for (int r = 0; r < 400; ++r) {
      Ray ray;
      for (int a = 0; a < 3; ++a)
        ray.origin[a] = tree.bounds.min[a] + u(rng) * (tree.bounds.max[a] - tree.bounds.min[a]);
      ray.dir = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)) + glm::vec3(1e-6f));
      rays.push_back(ray);
    }
    uint32_t hits = 0;
    for (const Ray& ray : rays) {
      Hit first;
      std::vector<uint32_t> first_visits;
      for (size_t k = 0; k < images.size(); ++k) {
        VisitSink sink{&node_at[k], {}, false};
        const MemoryImage& image = images[k];
        const Hit hit = with_layout_decoder(
            image, [&]<class D>() { return traverse<D>(image, ray, false, sink); });
        ASSERT_FALSE(sink.stray) << image.layout << ": fetch of a non-node";
        if (k == 0) {
          first = hit;
          first_visits = sink.visits;
          hits += hit.valid();
          continue;
        }
        EXPECT_EQ(hit.triangle, first.triangle) << image.layout;
        EXPECT_EQ(std::memcmp(&hit.t, &first.t, sizeof(float)), 0) << image.layout;
        EXPECT_EQ(sink.visits, first_visits) << image.layout;
      }
    }
    EXPECT_GT(hits, rays.size() / 4);
  }
}

// The aim for subtree: node memory at most 1.7x DFL's on the shared scenes big enough to fill
// blocks (box's tree has a handful of nodes; its few blocks cannot all be full).
TEST(LayoutsOnSharedScenes, SubtreeWithinTheMemoryAim) {
  namespace fs = std::filesystem;
  const std::string dir = RTUSIM_SCENES_DEFAULT;
  if (!fs::is_directory(dir)) RTUSIM_SKIP_UNLESS_CI("no scenes folder " + dir);
  for (const std::string name : {"cornell_whitted", "kitchen", "sponza_dabrovic"}) {
    const Scene scene = load_gltf(dir + "/" + name + "/" + name + ".gltf");
    const KdTree tree = build_sah_kd_tree(scene, KdBuildParams{});
    const MemoryImage dfl = make_layout("dfl")->build_image(tree, scene);
    const MemoryImage sub = make_layout("subtree")->build_image(tree, scene);
    const double ratio = double(sub.nodes.size_bytes) / double(dfl.nodes.size_bytes);
    const double fill = double(tree.nodes.size()) / double(sub.nodes.size_bytes / 64 * 5);
    std::cout << "[ subtree  ] " << name << ": " << ratio << "x DFL, block fill " << fill << "\n";
    EXPECT_LE(ratio, 1.7) << name;
    EXPECT_GE(fill, 0.95) << name;
  }
}

}  // namespace
}  // namespace rtusim
