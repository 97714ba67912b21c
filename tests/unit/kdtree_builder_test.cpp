// Tests of the SAH kd-tree builder: structural invariants and exact coverage on random soups with
// degenerate triangles, degenerate scenes, determinism, split quality and the depth limit.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <iterator>
#include <random>
#include <vector>

#include <glm/common.hpp>
#include <glm/vec3.hpp>
#include <gtest/gtest.h>

#include "kdtree/sah_builder.h"
#include "kdtree/triangle_clip.h"
#include "sanitized.h"

namespace rtusim {
namespace {

using Tri = std::array<glm::vec3, 3>;

Scene make_scene(const std::vector<Tri>& tris) {
  Scene scene;
  scene.source = "builtin:test";
  for (const Tri& t : tris) {
    const uint32_t base = static_cast<uint32_t>(scene.positions.size());
    for (const glm::vec3& p : t) scene.positions.push_back(p);
    scene.triangles.push_back({base, base + 1, base + 2});
    scene.triangle_material.push_back(0);
  }
  return scene;
}

// Independent exact-ish clipper for the checks: the triangle against a closed box in double.
// Returns the number of vertices of the clipped polygon (0: no intersection).
int clip_count(const Tri& tri, const glm::dvec3& lo, const glm::dvec3& hi) {
  std::vector<glm::dvec3> poly{glm::dvec3(tri[0]), glm::dvec3(tri[1]), glm::dvec3(tri[2])};
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const double plane = side == 0 ? lo[axis] : hi[axis];
      const double sign = side == 0 ? 1.0 : -1.0;
      std::vector<glm::dvec3> out;
      for (size_t i = 0; i < poly.size(); ++i) {
        const glm::dvec3 a = poly[i], b = poly[(i + 1) % poly.size()];
        const double da = sign * (a[axis] - plane), db = sign * (b[axis] - plane);
        if (da >= 0) out.push_back(a);
        if ((da < 0 && db > 0) || (da > 0 && db < 0)) out.push_back(a + (da / (da - db)) * (b - a));
      }
      poly.swap(out);
      if (poly.empty()) return 0;
    }
  }
  return static_cast<int>(poly.size());
}

// Whether the leaf with box `box` must hold `tri`: the triangle meets the box's interior (box
// shrunk by a tiny tolerance on each axis). A flat box (zero extent on an axis) has no interior:
// it lies in a split plane, and triangles in that plane may sit on either side of it; those are
// covered by `covered_by_leaves` instead.
bool must_contain(const Tri& tri, const Bounds3f& box, double tol) {
  glm::dvec3 lo(box.min), hi(box.max);
  for (int axis = 0; axis < 3; ++axis) {
    const double extent = hi[axis] - lo[axis];
    if (!(extent > 0.0)) return false;
    const double shrink = std::min(tol, 0.25 * extent);
    lo[axis] += shrink;
    hi[axis] -= shrink;
  }
  return clip_count(tri, lo, hi) > 0;
}

// Whether every sample point of the triangle (a barycentric grid, vertices included) lies in
// at least one leaf that lists the triangle. Points within `tol` of a plane go both ways.
bool covered_by_leaves(const KdTree& tree, const Tri& tri, uint32_t id, float tol) {
  constexpr int kSteps = 4;
  for (int i = 0; i <= kSteps; ++i)
    for (int j = 0; i + j <= kSteps; ++j) {
      const double a = double(i) / kSteps, b = double(j) / kSteps;
      const glm::vec3 p(glm::dvec3(tri[0]) * (1.0 - a - b) + glm::dvec3(tri[1]) * a +
                        glm::dvec3(tri[2]) * b);
      bool found = false;
      std::vector<uint32_t> stack{0};
      while (!stack.empty() && !found) {
        const KdNode& n = tree.nodes[stack.back()];
        stack.pop_back();
        if (n.is_leaf()) {
          const auto first = tree.refs.begin() + n.first_ref;
          found = std::binary_search(first, first + n.ref_count, id);
          continue;
        }
        if (p[n.axis] <= n.split + tol) stack.push_back(n.below);
        if (p[n.axis] >= n.split - tol) stack.push_back(n.above);
      }
      if (!found) return false;
    }
  return true;
}

// Whether the triangle's bounds touch the closed box (with tolerance).
bool touches(const Tri& tri, const Bounds3f& box, float tol) {
  Bounds3f b;
  for (const glm::vec3& p : tri) b.extend(p);
  for (int axis = 0; axis < 3; ++axis)
    if (b.max[axis] < box.min[axis] - tol || b.min[axis] > box.max[axis] + tol) return false;
  return true;
}

struct LeafInfo {
  uint32_t node;
  Bounds3f box;
  uint32_t depth;
};

// Walks the tree checking structure; returns the leaves with their boxes.
std::vector<LeafInfo> check_structure(const Scene& scene, const KdTree& tree) {
  std::vector<LeafInfo> leaves;
  EXPECT_FALSE(tree.nodes.empty());
  if (tree.nodes.empty()) return leaves;
  std::vector<int> visits(tree.nodes.size(), 0);
  std::vector<LeafInfo> stack{{0, tree.bounds, 0}};
  uint64_t ref_total = 0;
  std::vector<int> ref_used(tree.refs.size(), 0);
  while (!stack.empty()) {
    const LeafInfo item = stack.back();
    stack.pop_back();
    EXPECT_LT(item.node, tree.nodes.size());
    if (item.node >= tree.nodes.size()) continue;
    EXPECT_EQ(++visits[item.node], 1) << "node " << item.node << " reached twice";
    const KdNode& n = tree.nodes[item.node];
    if (n.is_leaf()) {
      leaves.push_back(item);
      EXPECT_LE(uint64_t(n.first_ref) + n.ref_count, tree.refs.size());
      if (uint64_t(n.first_ref) + n.ref_count > tree.refs.size()) continue;
      ref_total += n.ref_count;
      for (uint32_t r = n.first_ref; r < n.first_ref + n.ref_count; ++r) {
        EXPECT_EQ(++ref_used[r], 1) << "ref slot shared by two leaves";
        EXPECT_LT(tree.refs[r], scene.triangle_count());
        if (r > n.first_ref) EXPECT_LT(tree.refs[r - 1], tree.refs[r]) << "leaf ids not ascending";
      }
      continue;
    }
    EXPECT_LT(n.axis, 3);
    EXPECT_GE(n.split, item.box.min[n.axis]);
    EXPECT_LE(n.split, item.box.max[n.axis]);
    EXPECT_FALSE(std::isnan(n.split));
    const Bounds3f below = KdTree::below_bounds(n, item.box);
    const Bounds3f above = KdTree::above_bounds(n, item.box);
    for (const Bounds3f& child : {below, above})
      for (int axis = 0; axis < 3; ++axis) {
        EXPECT_GE(child.min[axis], item.box.min[axis]);
        EXPECT_LE(child.max[axis], item.box.max[axis]);
        EXPECT_LE(child.min[axis], child.max[axis]);
      }
    stack.push_back({n.above, above, item.depth + 1});
    stack.push_back({n.below, below, item.depth + 1});
  }
  for (size_t i = 0; i < visits.size(); ++i) EXPECT_EQ(visits[i], 1) << "node " << i << " unreachable";
  EXPECT_EQ(ref_total, tree.refs.size());
  return leaves;
}

// Triangle ids below `index` (sorted, unique); checks that every split makes progress: a child
// with the same box as its parent must hold fewer triangles.
std::vector<uint32_t> check_progress(const KdTree& tree, uint32_t index, const Bounds3f& box) {
  const KdNode& n = tree.nodes[index];
  if (n.is_leaf())
    return {tree.refs.begin() + n.first_ref, tree.refs.begin() + n.first_ref + n.ref_count};
  const Bounds3f below_box = KdTree::below_bounds(n, box), above_box = KdTree::above_bounds(n, box);
  const std::vector<uint32_t> below = check_progress(tree, n.below, below_box);
  const std::vector<uint32_t> above = check_progress(tree, n.above, above_box);
  std::vector<uint32_t> all;
  std::set_union(below.begin(), below.end(), above.begin(), above.end(), std::back_inserter(all));
  auto same_box = [&](const Bounds3f& b) { return b.min == box.min && b.max == box.max; };
  if (same_box(below_box)) EXPECT_LT(below.size(), all.size()) << "no progress below " << index;
  if (same_box(above_box)) EXPECT_LT(above.size(), all.size()) << "no progress above " << index;
  return all;
}

// Full invariant check: structure, exact coverage, leaf triangles touch their leaf, report.
void check_tree(const Scene& scene, const KdTree& tree, const KdBuildParams& params) {
  const std::vector<LeafInfo> leaves = check_structure(scene, tree);
  const uint32_t n = scene.triangle_count();
  if (!leaves.empty()) check_progress(tree, 0, tree.bounds);

  // Scene bounds.
  if (n == 0) {
    EXPECT_EQ(tree.bounds.min, glm::vec3(0.0f));
    EXPECT_EQ(tree.bounds.max, glm::vec3(0.0f));
  } else {
    EXPECT_EQ(tree.bounds.min, scene.bounds().min);
    EXPECT_EQ(tree.bounds.max, scene.bounds().max);
  }

  // Every leaf triangle touches its leaf; every triangle meeting a leaf's interior is in it.
  const double tol = 1e-5 * std::max(1.0f, tree.bounds.max_abs_coord());
  for (const LeafInfo& leaf : leaves) {
    const KdNode& node = tree.nodes[leaf.node];
    const auto first = tree.refs.begin() + node.first_ref;
    const auto last = first + node.ref_count;
    for (auto it = first; it != last; ++it)
      EXPECT_TRUE(touches(scene.vertices(*it), leaf.box, float(tol)))
          << "triangle " << *it << " does not touch leaf " << leaf.node;
    for (uint32_t t = 0; t < n; ++t) {
      const Tri tri = scene.vertices(t);
      if (!touches(tri, leaf.box, 0.0f) || !must_contain(tri, leaf.box, tol)) continue;
      EXPECT_TRUE(std::binary_search(first, last, t))
          << "triangle " << t << " overlaps leaf " << leaf.node << " but is missing";
    }
  }

  // Every part of every triangle is in some leaf whose box holds that part.
  for (uint32_t t = 0; t < n; ++t)
    EXPECT_TRUE(covered_by_leaves(tree, scene.vertices(t), t, float(tol)))
        << "triangle " << t << " is not covered by the leaves that list it";

  // Report recount.
  const KdTreeReport& r = tree.report;
  uint64_t empty = 0, filled = 0, depth_sum = 0;
  uint32_t max_depth = 0;
  double sah = 0.0;
  const double root_area = tree.bounds.surface_area();
  for (const LeafInfo& leaf : leaves) {
    const KdNode& node = tree.nodes[leaf.node];
    max_depth = std::max(max_depth, leaf.depth);
    if (node.ref_count == 0) ++empty;
    else ++filled, depth_sum += leaf.depth;
    sah += params.isect_cost * node.ref_count *
           (root_area > 0 ? leaf.box.surface_area() / root_area : 1.0);
  }
  // Interior nodes' traversal term, from a second walk.
  std::vector<std::pair<uint32_t, Bounds3f>> stack{{0, tree.bounds}};
  while (!stack.empty()) {
    auto [index, box] = stack.back();
    stack.pop_back();
    const KdNode& node = tree.nodes[index];
    if (node.is_leaf()) continue;
    sah += params.traversal_cost * (root_area > 0 ? box.surface_area() / root_area : 1.0);
    stack.push_back({node.below, KdTree::below_bounds(node, box)});
    stack.push_back({node.above, KdTree::above_bounds(node, box)});
  }
  EXPECT_EQ(r.nodes, tree.nodes.size());
  EXPECT_EQ(r.leaves, leaves.size());
  EXPECT_EQ(r.empty_leaves, empty);
  EXPECT_EQ(r.max_depth, max_depth);
  EXPECT_LE(int(r.max_depth), kd_max_depth(n, params));
  EXPECT_NEAR(r.mean_leaf_depth, filled ? double(depth_sum) / double(filled) : 0.0, 1e-9);
  EXPECT_NEAR(r.refs_per_triangle, n ? double(tree.refs.size()) / n : 0.0, 1e-12);
  EXPECT_NEAR(r.sah_cost, sah, 1e-6 * std::max(1.0, sah));
  EXPECT_GE(r.build_seconds, 0.0);
  EXPECT_GT(r.peak_build_bytes, 0u);
  EXPECT_EQ(r.nodes, r.leaves * 2 - 1);  // a full binary tree
}

// A random soup with degenerate members: flat in each axis, slivers, zero-area, duplicates and
// triangles on grid-aligned coordinates (where splits are likely to land).
std::vector<Tri> random_soup(uint32_t seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::uniform_int_distribution<int> grid(0, 8), kind(0, 9);
  auto point = [&] { return glm::vec3(unit(rng), unit(rng), unit(rng)) * 10.0f; };
  auto grid_value = [&] { return float(grid(rng)) * 1.25f; };
  std::vector<Tri> tris;
  while (int(tris.size()) < count) {
    const glm::vec3 c = point();
    const float size = 0.05f + unit(rng) * 1.5f;
    auto near = [&] { return c + (glm::vec3(unit(rng), unit(rng), unit(rng)) - 0.5f) * size; };
    Tri t{near(), near(), near()};
    switch (kind(rng)) {
      case 0: case 1: case 2: {  // flat in one axis, often on a grid plane
        const int axis = kind(rng) % 3;
        const float v = kind(rng) < 5 ? grid_value() : t[0][axis];
        for (auto& p : t) p[axis] = v;
        break;
      }
      case 3:  // sliver: third vertex almost on the first edge
        t[2] = t[0] + (t[1] - t[0]) * 0.5f + glm::vec3(1e-6f, 0.0f, 0.0f);
        break;
      case 4:  // zero area: collinear or a point
        t[2] = kind(rng) < 5 ? t[0] + (t[1] - t[0]) * 0.25f : t[0];
        if (kind(rng) < 3) t[1] = t[0];
        break;
      case 5:  // duplicate of an earlier triangle
        if (!tris.empty()) t = tris[std::uniform_int_distribution<size_t>(0, tris.size() - 1)(rng)];
        break;
      case 6:  // vertices on grid-aligned coordinates
        for (auto& p : t) p = glm::vec3(grid_value(), grid_value(), grid_value());
        break;
      default:
        break;
    }
    tris.push_back(t);
  }
  return tris;
}

TEST(KdTreeBuilder, RandomSoupsKeepInvariants) {
  for (uint32_t seed = 1; seed <= (testing::kSanitized ? 1u : 3u); ++seed) {
    const Scene scene = make_scene(random_soup(seed, 2500));
    const KdBuildParams params;
    const KdTree tree = build_sah_kd_tree(scene, params);
    SCOPED_TRACE(::testing::Message() << "seed " << seed);
    check_tree(scene, tree, params);
    EXPECT_GT(tree.report.leaves, 100u);  // it actually subdivided
    EXPECT_GE(tree.report.refs_per_triangle, 1.0);
  }
}

TEST(KdTreeBuilder, RandomSoupWithOtherParamsKeepsInvariants) {
  KdBuildParams params;
  params.isect_cost = 20.0f;
  params.empty_bonus = 0.8f;
  params.leaf_prims = 4;
  const Scene scene = make_scene(random_soup(7, 2000));
  const KdTree tree = build_sah_kd_tree(scene, params);
  check_tree(scene, tree, params);
}

TEST(KdTreeBuilder, ZeroTrianglesGiveOneEmptyLeaf) {
  const Scene scene = make_scene({});
  const KdBuildParams params;
  const KdTree tree = build_sah_kd_tree(scene, params);
  ASSERT_EQ(tree.nodes.size(), 1u);
  EXPECT_TRUE(tree.nodes[0].is_leaf());
  EXPECT_EQ(tree.nodes[0].ref_count, 0u);
  EXPECT_TRUE(tree.refs.empty());
  EXPECT_EQ(tree.report.empty_leaves, 1u);
  check_tree(scene, tree, params);
}

TEST(KdTreeBuilder, OneTriangleIsOneLeaf) {
  const Scene scene = make_scene({Tri{glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 1)}});
  const KdBuildParams params;
  const KdTree tree = build_sah_kd_tree(scene, params);
  ASSERT_EQ(tree.nodes.size(), 1u);
  ASSERT_EQ(tree.refs, std::vector<uint32_t>{0});
  check_tree(scene, tree, params);
}

TEST(KdTreeBuilder, IdenticalTrianglesTerminateSmall) {
  const Tri t{glm::vec3(0.1f, 0.2f, 0.3f), glm::vec3(1.7f, 0.4f, 0.9f), glm::vec3(0.5f, 2.1f, 1.3f)};
  const Scene scene = make_scene(std::vector<Tri>(1000, t));
  const KdBuildParams params;
  const KdTree tree = build_sah_kd_tree(scene, params);
  check_tree(scene, tree, params);
  EXPECT_LE(tree.nodes.size(), 16u);
  EXPECT_EQ(tree.refs.size(), 1000u);
}

TEST(KdTreeBuilder, IdenticalFlatTrianglesTerminateSmall) {
  const Tri t{glm::vec3(0.0f, 0.0f, 2.0f), glm::vec3(1.0f, 0.0f, 2.0f), glm::vec3(0.0f, 1.0f, 2.0f)};
  const Scene scene = make_scene(std::vector<Tri>(1000, t));
  const KdBuildParams params;
  const KdTree tree = build_sah_kd_tree(scene, params);
  check_tree(scene, tree, params);
  EXPECT_LE(tree.nodes.size(), 16u);
}

TEST(KdTreeBuilder, CoplanarSceneInAxisPlane) {
  // A 30x30 grid of triangles all in z = 1: the root box is flat and only x/y splits are useful.
  std::vector<Tri> tris;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) {
      const glm::vec3 o(float(i), float(j), 1.0f);
      tris.push_back({o, o + glm::vec3(1, 0, 0), o + glm::vec3(0, 1, 0)});
      tris.push_back({o + glm::vec3(1, 0, 0), o + glm::vec3(1, 1, 0), o + glm::vec3(0, 1, 0)});
    }
  const Scene scene = make_scene(tris);
  const KdBuildParams params;
  const KdTree tree = build_sah_kd_tree(scene, params);
  check_tree(scene, tree, params);
  EXPECT_GT(tree.report.leaves, 50u);
  EXPECT_EQ(tree.refs.size(), tris.size()) << "grid-aligned triangles touching a plane were split";
  for (const KdNode& n : tree.nodes)
    if (!n.is_leaf()) EXPECT_NE(n.axis, 2) << "split along the flat axis";
}

TEST(KdTreeBuilder, ManyTrianglesInOneSplitPlane) {
  // Walls of triangles lying in x = 5 plus random triangles on both sides and through it.
  std::vector<Tri> tris = random_soup(11, 1500);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 10.0f);
  for (int i = 0; i < 800; ++i) {
    const glm::vec3 a(5.0f, u(rng), u(rng));
    tris.push_back({a, a + glm::vec3(0, 0.7f, 0.1f), a + glm::vec3(0, 0.2f, 0.6f)});
  }
  const Scene scene = make_scene(tris);
  const KdBuildParams params;
  const KdTree tree = build_sah_kd_tree(scene, params);
  check_tree(scene, tree, params);
}

TEST(KdTreeBuilder, BoxFacesOfPlanarTriangles) {
  // Two parallel tessellated walls (like a room): planar triangles on the root box faces.
  std::vector<Tri> tris;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j)
      for (float x : {0.0f, 4.0f}) {
        const glm::vec3 o(x, float(i), float(j));
        tris.push_back({o, o + glm::vec3(0, 1, 0), o + glm::vec3(0, 0, 1)});
      }
  const Scene scene = make_scene(tris);
  const KdBuildParams params;
  const KdTree tree = build_sah_kd_tree(scene, params);
  check_tree(scene, tree, params);
}

TEST(KdTreeBuilder, DeterministicByteForByte) {
  const Scene scene = make_scene(random_soup(3, 3000));
  const KdBuildParams params;
  const KdTree a = build_sah_kd_tree(scene, params);
  const KdTree b = build_sah_kd_tree(scene, params);
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  ASSERT_EQ(a.refs.size(), b.refs.size());
  EXPECT_EQ(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(KdNode)), 0);
  EXPECT_EQ(std::memcmp(a.refs.data(), b.refs.data(), a.refs.size() * sizeof(uint32_t)), 0);
  for (size_t i = 0; i < a.nodes.size(); ++i) {
    EXPECT_EQ(a.nodes[i].axis, b.nodes[i].axis);
    EXPECT_EQ(a.nodes[i].split, b.nodes[i].split);
    EXPECT_EQ(a.nodes[i].below, b.nodes[i].below);
    EXPECT_EQ(a.nodes[i].above, b.nodes[i].above);
  }
  EXPECT_EQ(a.report.sah_cost, b.report.sah_cost);
}

TEST(KdTreeBuilder, RootSplitSeparatesFarClusters) {
  // Cluster A around x = 0, cluster B around x = 100.
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Tri> tris;
  for (int c = 0; c < 2; ++c)
    for (int i = 0; i < 200; ++i) {
      const glm::vec3 o(100.0f * c + u(rng) * 5, u(rng) * 5, u(rng) * 5);
      tris.push_back({o, o + glm::vec3(0.3f, 0, 0), o + glm::vec3(0, 0.3f, 0.2f)});
    }
  const Scene scene = make_scene(tris);
  const KdBuildParams params;
  const KdTree tree = build_sah_kd_tree(scene, params);
  check_tree(scene, tree, params);
  const KdNode& root = tree.nodes[0];
  ASSERT_FALSE(root.is_leaf());
  EXPECT_EQ(root.axis, 0);
  float a_max = -INFINITY, b_min = INFINITY;
  for (size_t i = 0; i < tris.size(); ++i)
    for (const glm::vec3& p : tris[i])
      (i < 200 ? a_max : b_min) = i < 200 ? std::max(a_max, p.x) : std::min(b_min, p.x);
  EXPECT_GE(root.split, a_max);
  EXPECT_LE(root.split, b_min);
}

// Tiny triangles at x = 2^-i: the SAH keeps peeling one off, so depth is limited only by the cap.
std::vector<Tri> geometric_chain(int count) {
  std::vector<Tri> tris;
  for (int i = 0; i < count; ++i) {
    const float s = std::ldexp(1.0f, -i);
    const glm::vec3 o(s, 0.0f, 0.0f);
    tris.push_back({o, o + glm::vec3(0.1f * s, 0, 0), o + glm::vec3(0, 0.1f * s, 0.1f * s)});
  }
  return tris;
}

TEST(KdTreeBuilder, DepthLimitRespected) {
  const Scene scene = make_scene(geometric_chain(40));
  KdBuildParams params;
  params.max_depth = 5;
  const KdTree tree = build_sah_kd_tree(scene, params);
  check_tree(scene, tree, params);
  EXPECT_EQ(tree.report.max_depth, 5u);
}

TEST(KdTreeBuilder, DefaultDepthLimitIsFormula) {
  EXPECT_EQ(kd_max_depth(0, KdBuildParams{}), 8);
  EXPECT_EQ(kd_max_depth(1, KdBuildParams{}), 8);
  EXPECT_EQ(kd_max_depth(1024, KdBuildParams{}), 21);            // 8 + 13
  EXPECT_EQ(kd_max_depth(66000, KdBuildParams{}), 29);           // 8 + 20.8
  KdBuildParams fixed;
  fixed.max_depth = 3;
  EXPECT_EQ(kd_max_depth(1000000, fixed), 3);

  const Scene scene = make_scene(geometric_chain(40));
  const KdBuildParams params;  // max_depth = -1
  const KdTree tree = build_sah_kd_tree(scene, params);
  check_tree(scene, tree, params);
  EXPECT_EQ(int(tree.report.max_depth), int(std::lround(8 + 1.3 * std::log2(40.0))));
}

TEST(KdTreeBuilder, LeafPrimsStopsEarly) {
  const Scene scene = make_scene(random_soup(4, 500));
  KdBuildParams params;
  params.leaf_prims = 1000;
  const KdTree tree = build_sah_kd_tree(scene, params);
  EXPECT_EQ(tree.nodes.size(), 1u);
  EXPECT_EQ(tree.refs.size(), 500u);
}

TEST(TriangleClip, ClippedBoundsStayInBoxAndCoverTheTriangle) {
  const Tri t{glm::vec3(-1, -1, 0.5f), glm::vec3(3, 0.2f, 0.5f), glm::vec3(0.1f, 3, 0.7f)};
  const Bounds3f box{glm::vec3(0), glm::vec3(1)};
  const Bounds3f b = clip_triangle_bounds(t, box);
  ASSERT_FALSE(b.empty());
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_GE(b.min[axis], box.min[axis]);
    EXPECT_LE(b.max[axis], box.max[axis]);
  }
  EXPECT_GT(b.min.z, 0.5f);  // the z = 0.5 corner lies outside the box
  EXPECT_LT(b.max.z, 0.7f);
  EXPECT_EQ(b.min.x, 0.0f);
  EXPECT_EQ(b.max.x, 1.0f);
  // A triangle entirely outside clips to nothing; one touching a face clips to that face.
  EXPECT_TRUE(clip_triangle_bounds({glm::vec3(2, 2, 2), glm::vec3(3, 2, 2), glm::vec3(2, 3, 2)}, box)
                  .empty());
  const Bounds3f touch =
      clip_triangle_bounds({glm::vec3(1, 0.2f, 0.2f), glm::vec3(2, 0.5f, 0.2f), glm::vec3(1, 0.6f, 0.9f)}, box);
  ASSERT_FALSE(touch.empty());
  EXPECT_EQ(touch.min.x, 1.0f);
  EXPECT_EQ(touch.max.x, 1.0f);
}

TEST(TriangleClip, FallbackClampNeverEmptyAndInsideBox) {
  // What the builder uses when rounding empties a clip: bounds clamped into the child box.
  const Bounds3f box{glm::vec3(0), glm::vec3(1)};
  const Bounds3f outside{glm::vec3(1.0000001f, 0.2f, -3), glm::vec3(2, 0.4f, -2)};
  const Bounds3f c = clamp_bounds_into(outside, box);
  ASSERT_FALSE(c.empty());
  EXPECT_EQ(c.min, glm::vec3(1, 0.2f, 0));
  EXPECT_EQ(c.max, glm::vec3(1, 0.4f, 0));
}

}  // namespace
}  // namespace rtusim
