// Geometry for tests: random triangle soups with degenerate cases, and closed meshes.
#pragma once
#include <cmath>
#include <glm/geometric.hpp>
#include <map>
#include <random>

#include "scene/scene.h"

namespace rtusim::testing {

inline uint32_t add_vertex(Scene& s, const glm::vec3& p) {
  s.positions.push_back(p);
  s.normals.push_back(glm::vec3(0.0f));
  return static_cast<uint32_t>(s.positions.size() - 1);
}

inline void add_triangle(Scene& s, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  s.triangles.push_back({add_vertex(s, a), add_vertex(s, b), add_vertex(s, c)});
  s.triangle_material.push_back(0);
}

inline void finish(Scene& s) {
  if (s.materials.empty()) s.materials.push_back(Material{});
}

// A coarse coordinate (multiples of 1/8 in [-4, 4]): triangles of such vertices share exact
// edges and vertices, and rays through them meet zero barycentrics; else a fine random one.
inline float random_coordinate(std::mt19937& rng, bool coarse) {
  if (coarse) return static_cast<float>(static_cast<int>(rng() % 65) - 32) / 8.0f;
  return std::uniform_real_distribution<float>(-4.0f, 4.0f)(rng);
}

// A soup of small random triangles in [-1,1]^3 with degenerate members: axis-aligned flat
// ones, slivers, zero-area, duplicates, and triangles on grid planes (likely split planes).
inline Scene random_soup(uint32_t seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(-1.0f, 1.0f), size(0.01f, 0.3f);
  std::uniform_int_distribution<int> kind(0, 9), axis(0, 2), grid(-4, 4);
  Scene s;
  for (int i = 0; i < count; ++i) {
    const glm::vec3 c(pos(rng), pos(rng), pos(rng));
    const float r = size(rng);
    glm::vec3 a = c + r * glm::vec3(pos(rng), pos(rng), pos(rng));
    glm::vec3 b = c + r * glm::vec3(pos(rng), pos(rng), pos(rng));
    glm::vec3 d = c + r * glm::vec3(pos(rng), pos(rng), pos(rng));
    switch (kind(rng)) {
      case 0: {  // flat in an axis plane, on a grid value
        const int ax = axis(rng);
        a[ax] = b[ax] = d[ax] = grid(rng) * 0.25f;
        break;
      }
      case 1: d = a + (b - a) * 0.5f + glm::vec3(1e-6f, 0, 0); break;  // sliver
      case 2: d = b; break;                                             // zero area
      case 3:                                                           // duplicate
        if (!s.triangles.empty()) {
          const auto v = s.vertices(static_cast<uint32_t>(s.triangles.size() - 1));
          a = v[0], b = v[1], d = v[2];
        }
        break;
      default: break;
    }
    add_triangle(s, a, b, d);
  }
  finish(s);
  return s;
}

// A closed icosphere (shared vertices, consistent outward winding), radius r at centre c.
inline void add_icosphere(Scene& s, const glm::vec3& c, float r, int subdivisions) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<glm::vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                              {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                              {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<uint32_t, 3>> f = {
      {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
      {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (auto& p : v) p = glm::normalize(p);
  for (int k = 0; k < subdivisions; ++k) {
    std::vector<std::array<uint32_t, 3>> next;
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      if (auto it = mid.find(key); it != mid.end()) return it->second;
      v.push_back(glm::normalize(v[a] + v[b]));
      return mid[key] = static_cast<uint32_t>(v.size() - 1);
    };
    for (const auto& tri : f) {
      const uint32_t a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]),
                     d = midpoint(tri[2], tri[0]);
      next.push_back({tri[0], a, d});
      next.push_back({tri[1], b, a});
      next.push_back({tri[2], d, b});
      next.push_back({a, b, d});
    }
    f = std::move(next);
  }
  const uint32_t base = static_cast<uint32_t>(s.positions.size());
  for (const auto& p : v) {
    s.positions.push_back(c + r * p);
    s.normals.push_back(p);
  }
  for (const auto& tri : f) {
    s.triangles.push_back({base + tri[0], base + tri[1], base + tri[2]});
    s.triangle_material.push_back(0);
  }
}

// A closed axis-aligned box split into an n x n grid per face (shared vertices on edges).
inline void add_grid_box(Scene& s, const glm::vec3& lo, const glm::vec3& hi, int n) {
  std::map<std::array<int, 3>, uint32_t> index;
  auto vertex = [&](int i, int j, int k) {
    const std::array<int, 3> key{i, j, k};
    if (auto it = index.find(key); it != index.end()) return it->second;
    const glm::vec3 p = lo + (hi - lo) * glm::vec3(i, j, k) / float(n);
    return index[key] = add_vertex(s, p);
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side <= 1; ++side)
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
          auto at = [&](int da, int db) {
            std::array<int, 3> g{};
            g[axis] = side * n;
            g[(axis + 1) % 3] = a + da;
            g[(axis + 2) % 3] = b + db;
            return vertex(g[0], g[1], g[2]);
          };
          const uint32_t v00 = at(0, 0), v10 = at(1, 0), v01 = at(0, 1), v11 = at(1, 1);
          s.triangles.push_back({v00, v10, v11});
          s.triangles.push_back({v00, v11, v01});
          s.triangle_material.push_back(0);
          s.triangle_material.push_back(0);
        }
}

}  // namespace rtusim::testing
