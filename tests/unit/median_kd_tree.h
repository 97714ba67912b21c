// Test helpers that need no SAH builder: a random triangle soup and a valid kd-tree over it,
// built by simple median splits. Node indices are in breadth-first order, unlike any layout's.
#pragma once
#include <algorithm>
#include <cstdint>
#include <deque>
#include <random>
#include <vector>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include "kdtree/kd_tree.h"
#include "scene/scene.h"

namespace rtusim::testing {

// `count` random triangles in the unit cube, denser toward the origin: mostly small, some large, some lying in the
// axis-aligned planes x, y or z = 0.5 (so split planes and triangles coincide).
inline Scene random_soup(uint32_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), edge(-0.05f, 0.05f);
  Scene scene;
  scene.source = "test:soup";
  scene.materials.push_back(Material{});
  for (uint32_t t = 0; t < count; ++t) {
    glm::vec3 c(unit(rng), unit(rng), unit(rng));
    c = c * c * c;  // dense near the origin, sparse (and empty leaves) toward (1, 1, 1)
    const float scale = (t % 50 == 0) ? 6.0f : 1.0f;
    glm::vec3 v[3];
    for (auto& p : v) {
      p = c + scale * glm::vec3(edge(rng), edge(rng), edge(rng));
      p = glm::clamp(p, glm::vec3(0.0f), glm::vec3(1.0f));
    }
    if (t % 17 == 0) {
      const int a = static_cast<int>(t / 17 % 3);
      for (auto& p : v) p[a] = 0.5f;
    }
    const auto base = static_cast<uint32_t>(scene.positions.size());
    for (const auto& p : v) scene.positions.push_back(p);
    scene.normals.insert(scene.normals.end(), 3, glm::vec3(0.0f));
    scene.triangles.push_back({base, base + 1, base + 2});
    scene.triangle_material.push_back(0);
  }
  return scene;
}

// A valid kd-tree over `scene`: each node splits its longest axis at the median of its
// triangles' centroids or (at random) at the box's midpoint, which leaves empty leaves too.
// A triangle goes to every child its bounding box touches (closed intervals). A node whose
// split would duplicate more than half its triangles stays a leaf.
inline KdTree build_median_kd_tree(const Scene& scene, uint32_t leaf_prims, int max_depth,
                                   uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<Bounds3f> tri_box(scene.triangle_count());
  for (uint32_t t = 0; t < scene.triangle_count(); ++t)
    for (const auto& p : scene.vertices(t)) tri_box[t].extend(p);

  KdTree tree;
  tree.bounds = scene.bounds();
  struct Work {
    uint32_t node;
    Bounds3f box;
    std::vector<uint32_t> tris;
    int depth;
  };
  std::deque<Work> work;
  std::vector<uint32_t> all(scene.triangle_count());
  for (uint32_t t = 0; t < all.size(); ++t) all[t] = t;
  tree.nodes.emplace_back();
  work.push_back({0, tree.bounds, std::move(all), 0});

  while (!work.empty()) {
    Work w = std::move(work.front());
    work.pop_front();
    const glm::vec3 d = w.box.diagonal();
    const int axis = (d.x >= d.y && d.x >= d.z) ? 0 : (d.y >= d.z ? 1 : 2);
    float split = 0.5f * (w.box.min[axis] + w.box.max[axis]);
    if (!w.tris.empty() && rng() % 2 == 0) {
      std::vector<float> c;
      for (uint32_t t : w.tris) c.push_back(0.5f * (tri_box[t].min[axis] + tri_box[t].max[axis]));
      std::nth_element(c.begin(), c.begin() + c.size() / 2, c.end());
      split = std::clamp(c[c.size() / 2], w.box.min[axis], w.box.max[axis]);
    }
    std::vector<uint32_t> below, above;
    for (uint32_t t : w.tris) {
      if (tri_box[t].min[axis] <= split) below.push_back(t);
      if (tri_box[t].max[axis] >= split) above.push_back(t);
    }
    // Stop where splitting only duplicates references (large overlapping triangles).
    const bool no_progress = below.size() + above.size() > w.tris.size() * 3 / 2;
    if (w.tris.size() <= leaf_prims || w.depth >= max_depth || no_progress) {
      KdNode& leaf = tree.nodes[w.node];
      leaf.axis = KdNode::kLeaf;
      leaf.first_ref = static_cast<uint32_t>(tree.refs.size());
      leaf.ref_count = static_cast<uint32_t>(w.tris.size());
      tree.refs.insert(tree.refs.end(), w.tris.begin(), w.tris.end());
      continue;
    }
    const auto b = static_cast<uint32_t>(tree.nodes.size());
    tree.nodes.emplace_back();
    tree.nodes.emplace_back();
    KdNode& n = tree.nodes[w.node];
    n.axis = static_cast<uint8_t>(axis);
    n.split = split;
    n.below = b;
    n.above = b + 1;
    work.push_back({b, KdTree::below_bounds(n, w.box), std::move(below), w.depth + 1});
    work.push_back({b + 1, KdTree::above_bounds(n, w.box), std::move(above), w.depth + 1});
  }
  tree.report.nodes = tree.nodes.size();
  return tree;
}

// A random soup with its median tree: leaf sizes vary so that empty, inline and list leaves all
// occur.
struct SoupTree {
  Scene scene;
  KdTree tree;
};

inline SoupTree soup_tree(uint32_t triangles, uint32_t leaf_prims, uint32_t seed) {
  SoupTree f;
  f.scene = random_soup(triangles, seed);
  f.tree = build_median_kd_tree(f.scene, leaf_prims, 20, seed + 1);
  return f;
}

}  // namespace rtusim::testing
