// Layouts: every layout round-trips the logical tree, keeps its own placement rules, fetches
// only real node addresses, and gives traversal exactly the same hits as every other layout.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iostream>
#include <map>
#include <random>
#include <set>
#include <string>

#include <glm/geometric.hpp>

#include "layout/dfl_layout.h"
#include "layout/layout.h"
#include "layout/layout_dispatch.h"
#include "layout/odfl_layout.h"
#include "layout/subtree_layout.h"
#include "layout/tree_measures.h"
#include "median_kd_tree.h"
#include "traversal/traversal.h"
#include "util/error.h"

namespace rtusim {
namespace {


using Fixture = testing::SoupTree;
constexpr auto make_fixture = testing::soup_tree;

MemoryImage image_of(const std::string& kind, const Fixture& f) {
  return make_layout(kind)->build_image(f.tree, f.scene);
}

NodeView decode(const MemoryImage& image, uint64_t addr) {
  return with_layout_decoder(image, [&]<class Decoder>() { return Decoder::decode(image, addr); });
}

// Walks the image from its root alongside the logical tree, checking every decoded node
// against its logical node; returns the address of each logical node.
std::vector<uint64_t> round_trip(const MemoryImage& image, const KdTree& tree) {
  std::vector<uint64_t> addr_of(tree.nodes.size(), ~uint64_t{0});
  std::set<uint64_t> seen;
  std::vector<std::pair<uint32_t, uint64_t>> stack{{0u, image.root_addr}};
  while (!stack.empty()) {
    const auto [i, addr] = stack.back();
    stack.pop_back();
    EXPECT_TRUE(seen.insert(addr).second) << "two nodes at address " << addr;
    addr_of[i] = addr;
    const KdNode& n = tree.nodes[i];
    const NodeView v = decode(image, addr);
    EXPECT_EQ(v.leaf, n.is_leaf()) << "node " << i;
    if (v.leaf != n.is_leaf()) continue;
    if (n.is_leaf()) {
      EXPECT_EQ(v.prim_count, n.ref_count) << "node " << i;
      if (v.prim_count != n.ref_count) continue;
      for (uint32_t r = 0; r < n.ref_count; ++r) {
        const uint32_t tri = n.ref_count == 1 ? v.inline_prim
                                              : image.load<uint32_t>(v.list_addr + 4ull * r);
        EXPECT_EQ(tri, tree.refs[n.first_ref + r]) << "node " << i << " entry " << r;
      }
      if (n.ref_count >= 2) {
        EXPECT_GE(v.list_addr, image.lists.base_addr);
        EXPECT_LE(v.list_addr + 4ull * n.ref_count, image.lists.end_addr());
      }
    } else {
      EXPECT_EQ(v.axis, n.axis) << "node " << i;
      EXPECT_EQ(std::memcmp(&v.split, &n.split, sizeof(float)), 0) << "node " << i;
      stack.push_back({n.above, v.above_addr});
      stack.push_back({n.below, v.below_addr});
    }
  }
  EXPECT_EQ(seen.size(), tree.nodes.size()) << "reachable nodes";
  return addr_of;
}

const std::vector<std::string> kKinds = {"dfl",         "odfl", "subtree", "subtree-bfs",
                                          "veb",         "cluster", "profile"};

bool is_subtree(const std::string& kind) { return kind == "subtree" || kind == "subtree-bfs"; }

TEST(Layout, KindsAndUnknownName) {
  EXPECT_EQ(layout_kinds(), kKinds);
  for (const auto& k : kKinds) EXPECT_EQ(make_layout(k)->name(), k);
  try {
    make_layout("bvh");
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("layout.kind"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'bvh'"), std::string::npos) << msg;
    for (const auto& k : kKinds) EXPECT_NE(msg.find(k), std::string::npos) << msg;
  }
}

TEST(Layout, RoundTripEveryNode) {
  uint32_t inline_leaves = 0, list_leaves = 0, empty_leaves = 0;
  for (uint32_t leaf_prims : {1u, 2u, 6u}) {
    const Fixture f = make_fixture(2000, leaf_prims, 7 + leaf_prims);
    for (const KdNode& n : f.tree.nodes)
      if (n.is_leaf()) (n.ref_count == 0 ? empty_leaves : n.ref_count == 1 ? inline_leaves
                                                                           : list_leaves)++;
    for (const auto& kind : kKinds) {
      SCOPED_TRACE(kind + " leaf_prims " + std::to_string(leaf_prims));
      const MemoryImage image = image_of(kind, f);
      EXPECT_EQ(image.layout, kind);
      EXPECT_EQ(image.node_bytes, is_subtree(kind) ? 12u : 8u);
      EXPECT_EQ(image.nodes.base_addr % 64, 0u);
      EXPECT_EQ(image.lists.base_addr % 64, 0u);
      EXPECT_EQ(image.triangles.base_addr % 64, 0u);
      round_trip(image, f.tree);
    }
  }
  // The trees had leaves of every kind: empty, one inline triangle, a list.
  EXPECT_GT(empty_leaves, 0u);
  EXPECT_GT(inline_leaves, 0u);
  EXPECT_GT(list_leaves, 0u);
}

TEST(Layout, SingleLeafTree) {
  const Fixture f = make_fixture(3, 8, 3);
  ASSERT_EQ(f.tree.nodes.size(), 1u);
  for (const auto& kind : kKinds) {
    SCOPED_TRACE(kind);
    round_trip(image_of(kind, f), f.tree);
  }
}

TEST(OdflLayout, LargerChildIsAdjacentAndFlagSaysWhich) {
  const Fixture f = make_fixture(3000, 2, 11);
  const MemoryImage image = image_of("odfl", f);
  const std::vector<uint64_t> addr_of = round_trip(image, f.tree);
  uint32_t flipped = 0, interior = 0;
  std::vector<std::pair<uint32_t, Bounds3f>> stack{{0u, f.tree.bounds}};
  while (!stack.empty()) {
    const auto [i, box] = stack.back();
    stack.pop_back();
    const KdNode& n = f.tree.nodes[i];
    if (n.is_leaf()) continue;
    ++interior;
    const Bounds3f below = KdTree::below_bounds(n, box), above = KdTree::above_bounds(n, box);
    const bool above_larger = above.surface_area() > below.surface_area();
    const uint64_t addr = addr_of[i];
    EXPECT_EQ(addr_of[above_larger ? n.above : n.below], addr + 8) << "node " << i;
    const uint32_t w0 = image.load<uint32_t>(addr);
    EXPECT_EQ((w0 & OdflLayout::kReorderBit) != 0, addr_of[n.above] == addr + 8) << "node " << i;
    flipped += above_larger;
    stack.push_back({n.below, below});
    stack.push_back({n.above, above});
  }
  // Both orders occur, so the test exercises the flag both ways.
  EXPECT_GT(flipped, 0u);
  EXPECT_LT(flipped, interior);
}

TEST(OdflLayout, NoMemoryBeyondDfl) {
  const Fixture f = make_fixture(3000, 2, 12);
  const MemoryImage dfl = image_of("dfl", f), odfl = image_of("odfl", f);
  EXPECT_EQ(odfl.nodes.size_bytes, dfl.nodes.size_bytes);
  EXPECT_EQ(odfl.nodes.size_bytes, f.tree.nodes.size() * 8);
  EXPECT_EQ(odfl.bytes.size(), dfl.bytes.size());
}

TEST(SubtreeLayout, BfsBlocksAreConnectedSubtreesOfAtMostFive) {
  for (uint32_t seed : {21u, 22u}) {
    const Fixture f = make_fixture(3000, 2, seed);
    const MemoryImage image = image_of("subtree-bfs", f);
    const std::vector<uint64_t> addr_of = round_trip(image, f.tree);
    EXPECT_EQ(image.nodes.size_bytes % 64, 0u);
    EXPECT_EQ(image.root_addr, image.nodes.base_addr);

    std::vector<uint32_t> parent(f.tree.nodes.size(), ~0u);
    for (uint32_t i = 0; i < f.tree.nodes.size(); ++i)
      if (!f.tree.nodes[i].is_leaf()) parent[f.tree.nodes[i].below] = parent[f.tree.nodes[i].above] = i;
    auto block_of = [&](uint32_t i) { return (addr_of[i] - image.nodes.base_addr) / 64; };

    std::map<uint64_t, uint32_t> nodes_in, roots_in;
    std::set<uint64_t> open_blocks;  // blocks with a child outside them
    for (uint32_t i = 0; i < f.tree.nodes.size(); ++i) {
      const uint64_t off = addr_of[i] - image.nodes.base_addr;
      EXPECT_EQ(off % 64 % 12, 0u) << "node " << i;
      EXPECT_LT(off % 64 / 12, 5u) << "node " << i;
      EXPECT_LE(off % 64 + 12, 64u) << "node " << i << " straddles a line";
      ++nodes_in[block_of(i)];
      if (parent[i] == ~0u || block_of(parent[i]) != block_of(i)) {
        ++roots_in[block_of(i)];
        if (parent[i] != ~0u) open_blocks.insert(block_of(parent[i]));
      }
    }
    EXPECT_EQ(nodes_in.size() * 64, image.nodes.size_bytes) << "every block holds nodes";
    for (const auto& [block, count] : nodes_in) {
      EXPECT_LE(count, 5u) << "block " << block;
      EXPECT_EQ(roots_in[block], 1u) << "block " << block << " is not one connected subtree";
      // Breadth-first fill stops short of five only when the block's subtree is exhausted.
      if (count < 5) {
        EXPECT_FALSE(open_blocks.count(block)) << "block " << block;
      }
    }
  }
}

TEST(SubtreeLayout, SharedBlocksHoldWholeSmallSubtreesAndBigOnesStartBlocks) {
  for (uint32_t seed : {23u, 24u}) {
    const Fixture f = make_fixture(3000, 2, seed);
    const MemoryImage image = image_of("subtree", f);
    const std::vector<uint64_t> addr_of = round_trip(image, f.tree);
    const std::vector<uint32_t> size = subtree_node_counts(f.tree);
    auto block_of = [&](uint32_t i) { return (addr_of[i] - image.nodes.base_addr) / 64; };
    std::map<uint64_t, uint32_t> nodes_in;
    uint32_t small_roots = 0;
    for (uint32_t i = 0; i < f.tree.nodes.size(); ++i) {
      const uint64_t off = addr_of[i] - image.nodes.base_addr;
      EXPECT_LE(off % 64 + 12, 64u) << "node " << i << " straddles a line";
      ++nodes_in[block_of(i)];
      const KdNode& n = f.tree.nodes[i];
      if (n.is_leaf()) continue;
      for (const uint32_t c : {n.below, n.above}) {
        if (block_of(c) == block_of(i)) continue;
        // A child outside its parent's block roots a subtree: a small one whole in its block,
        // a big one at slot 0 of a block of its own.
        if (size[c] < 5) {
          ++small_roots;
          std::vector<uint32_t> stack{c};
          while (!stack.empty()) {
            const uint32_t d = stack.back();
            stack.pop_back();
            EXPECT_EQ(block_of(d), block_of(c)) << "small subtree of " << c << " split";
            if (!f.tree.nodes[d].is_leaf()) stack.insert(stack.end(), {f.tree.nodes[d].below, f.tree.nodes[d].above});
          }
        } else {
          EXPECT_EQ(addr_of[c] % 64, 0u) << "node " << c;
        }
      }
    }
    EXPECT_GT(small_roots, 0u);
    uint32_t full = 0;
    for (const auto& [block, count] : nodes_in) {
      EXPECT_LE(count, 5u);
      full += count == 5;
    }
    // The aim: blocks nearly full.
    EXPECT_GE(double(f.tree.nodes.size()) / double(nodes_in.size() * 5), 0.9);
    EXPECT_GT(full, nodes_in.size() * 8 / 10);
  }
}

TEST(SubtreeLayout, NodeBytesAgainstDfl) {
  // Five 12-byte nodes per 64-byte block against eight 8-byte nodes: 1.6x DFL's bytes when every
  // block is full; the aim for shared blocks is at most 1.7x. One subtree per block leaves
  // small subtrees' blocks partly empty: more.
  for (uint32_t leaf_prims : {1u, 2u, 4u}) {
    const Fixture f = make_fixture(4000, leaf_prims, 31 + leaf_prims);
    const MemoryImage dfl = image_of("dfl", f), sub = image_of("subtree", f),
                      bfs = image_of("subtree-bfs", f);
    const double ratio = double(sub.nodes.size_bytes) / double(dfl.nodes.size_bytes);
    const double bfs_ratio = double(bfs.nodes.size_bytes) / double(dfl.nodes.size_bytes);
    std::cout << "[ ratio    ] leaf_prims " << leaf_prims << ": " << f.tree.nodes.size()
              << " nodes, dfl " << dfl.nodes.size_bytes << " B, subtree " << sub.nodes.size_bytes
              << " B (" << ratio << "x), subtree-bfs " << bfs.nodes.size_bytes << " B ("
              << bfs_ratio << "x)\n";
    RecordProperty("subtree_over_dfl_leaf_prims_" + std::to_string(leaf_prims),
                   std::to_string(ratio));
    EXPECT_GE(ratio, 1.6);
    EXPECT_LE(ratio, 1.7);
    EXPECT_GT(bfs_ratio, ratio);
  }
}

// Records node fetches in issue order and checks each fetch's size.
struct CountingSink {
  std::vector<uint64_t> node_addrs;
  uint64_t list_fetches = 0, triangle_fetches = 0;
  uint32_t node_bytes = 0;
  bool bad_size = false;
  void fetch(Stream s, uint64_t addr, uint32_t bytes) {
    if (s == Stream::kNode) {
      node_addrs.push_back(addr);
      bad_size |= bytes != node_bytes;
    } else if (s == Stream::kList) {
      ++list_fetches;
    } else {
      ++triangle_fetches;
      bad_size |= bytes != MemoryImage::kTriangleBytes;
    }
  }
};

Hit brute_force(const Scene& scene, const Ray& ray) {
  const WatertightRay w(ray.origin, ray.dir);
  Hit best;
  best.t = ray.t_max;
  for (uint32_t t = 0; t < scene.triangle_count(); ++t) {
    const auto v = scene.vertices(t);
    float th, u, vv;
    if (intersect_watertight(w, v[0], v[1], v[2], best.t, th, u, vv)) best = {th, t, u, vv};
  }
  if (!best.valid()) best.t = std::numeric_limits<float>::infinity();
  return best;
}

// Random rays for the soup in the unit cube: general, axis-parallel, starting on split planes
// (some lying in them), and from outside the scene.
std::vector<Ray> random_rays(const KdTree& tree, uint32_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), wide(-0.5f, 1.5f);
  std::normal_distribution<float> gauss;
  std::vector<uint32_t> interior;
  for (uint32_t i = 0; i < tree.nodes.size(); ++i)
    if (!tree.nodes[i].is_leaf()) interior.push_back(i);
  std::vector<Ray> rays;
  for (uint32_t r = 0; r < count; ++r) {
    Ray ray;
    ray.origin = glm::vec3(unit(rng), unit(rng), unit(rng));
    ray.dir = glm::vec3(gauss(rng), gauss(rng), gauss(rng));
    switch (r % 6) {
      case 0: break;
      case 1: {  // along one axis
        const int a = static_cast<int>(rng() % 3);
        ray.dir = glm::vec3(0.0f);
        ray.dir[a] = rng() % 2 ? 1.0f : -1.0f;
        break;
      }
      case 2:  // in an axis-aligned plane
        ray.dir[rng() % 3] = 0.0f;
        break;
      case 3: {  // from a split plane, sometimes in it
        const KdNode& n = tree.nodes[interior[rng() % interior.size()]];
        ray.origin[n.axis] = n.split;
        if (rng() % 3 == 0) ray.dir[n.axis] = 0.0f;
        break;
      }
      case 4: {  // from a split plane along its normal or along another axis
        const KdNode& n = tree.nodes[interior[rng() % interior.size()]];
        ray.origin[n.axis] = n.split;
        ray.dir = glm::vec3(0.0f);
        ray.dir[rng() % 2 ? n.axis : (n.axis + 1) % 3] = rng() % 2 ? 1.0f : -1.0f;
        break;
      }
      case 5:  // from around the scene, toward its middle
        ray.origin = glm::vec3(wide(rng), wide(rng), wide(rng)) * 2.0f - 0.5f;
        ray.dir = glm::vec3(0.5f) + 0.3f * ray.dir - ray.origin;
        break;
    }
    if (glm::length(ray.dir) == 0.0f) ray.dir = glm::vec3(0.0f, 0.0f, 1.0f);
    rays.push_back(ray);
  }
  return rays;
}

TEST(Layout, IdenticalHitsAndValidFetchAddresses) {
  for (uint32_t seed : {41u, 42u, 43u}) {
    const Fixture f = make_fixture(3000, seed == 43u ? 1u : 3u, seed);
    std::vector<MemoryImage> images;
    std::vector<std::vector<uint64_t>> addr_of;
    std::vector<std::map<uint64_t, uint32_t>> node_at;  // address -> logical node
    for (const auto& k : kKinds) {
      images.push_back(image_of(k, f));
      addr_of.push_back(round_trip(images.back(), f.tree));
      node_at.emplace_back();
      for (uint32_t i = 0; i < addr_of.back().size(); ++i) node_at.back()[addr_of.back()[i]] = i;
    }
    const std::vector<Ray> rays = random_rays(f.tree, 2400, seed);
    uint32_t hits = 0, ties = 0, shadow_hits = 0;
    for (size_t r = 0; r < rays.size(); ++r) {
      const Hit expect = brute_force(f.scene, rays[r]);
      // Shadow ray: the same ray, limited to somewhat before or after the closest hit.
      Ray shadow = rays[r];
      shadow.t_max = expect.valid() ? expect.t * (r % 2 ? 0.999f : 1.001f) : 10.0f;
      const bool expect_shadow_hit = brute_force(f.scene, shadow).valid();

      Hit first_hit, first_any;
      std::vector<uint32_t> first_visits;
      for (size_t k = 0; k < kKinds.size(); ++k) {
        const MemoryImage& image = images[k];
        CountingSink sink;
        sink.node_bytes = image.node_bytes;
        const Hit hit = with_layout_decoder(image, [&]<class D>() {
          return traverse<D>(image, rays[r], false, sink);
        });
        NullFetchSink none;
        const Hit any = with_layout_decoder(image, [&]<class D>() {
          return traverse<D>(image, shadow, true, none);
        });
        SCOPED_TRACE(kKinds[k] + " seed " + std::to_string(seed) + " ray " + std::to_string(r));
        EXPECT_FALSE(sink.bad_size);

        // Every node fetch is a node of this layout, at a legal node address.
        std::vector<uint32_t> visits;
        for (const uint64_t a : sink.node_addrs) {
          ASSERT_GE(a, image.nodes.base_addr);
          ASSERT_LE(a + image.node_bytes, image.nodes.end_addr());
          const uint64_t off = a - image.nodes.base_addr;
          if (is_subtree(kKinds[k])) {
            ASSERT_EQ(off % 64 % 12, 0u);
            ASSERT_LT(off % 64 / 12, 5u);
          } else {
            ASSERT_EQ(off % image.node_bytes, 0u);
          }
          const auto it = node_at[k].find(a);
          ASSERT_NE(it, node_at[k].end()) << "fetch of a non-node at " << a;
          visits.push_back(it->second);
        }

        if (k == 0) {
          first_hit = hit;
          first_any = any;
          first_visits = visits;
          // Against brute force: same t (to 1e-6 relative), same triangle unless tied in t.
          ASSERT_EQ(hit.valid(), expect.valid());
          if (hit.valid()) {
            ++hits;
            EXPECT_NEAR(hit.t, expect.t, 1e-6 * expect.t);
            if (hit.triangle != expect.triangle) {
              // A tie: another triangle at the same distance (overlapping coplanar ones).
              ++ties;
              const auto v = f.scene.vertices(hit.triangle);
              float t, u, w;
              ASSERT_TRUE(intersect_watertight(WatertightRay(rays[r].origin, rays[r].dir), v[0],
                                               v[1], v[2], rays[r].t_max, t, u, w));
              EXPECT_EQ(t, hit.t);
            }
          }
          ASSERT_EQ(any.valid(), expect_shadow_hit);
          if (any.valid()) {
            ++shadow_hits;
            EXPECT_LT(any.t, shadow.t_max);
          }
        } else {
          // Across layouts: bit-identical results and the same logical visit order.
          EXPECT_EQ(hit.triangle, first_hit.triangle);
          EXPECT_EQ(std::memcmp(&hit.t, &first_hit.t, sizeof(float)), 0);
          EXPECT_EQ(any.triangle, first_any.triangle);
          EXPECT_EQ(std::memcmp(&any.t, &first_any.t, sizeof(float)), 0);
          EXPECT_EQ(visits, first_visits);
        }
      }
    }
    std::cout << "[ hits     ] seed " << seed << ": " << hits << "/" << rays.size()
              << " closest hits (" << ties << " ties), " << shadow_hits << " shadow hits\n";
    EXPECT_GT(hits, rays.size() / 4);
    EXPECT_GT(shadow_hits, rays.size() / 8);
  }
}

}  // namespace
}  // namespace rtusim
