// Kd-tree traversal against brute force on random soups (degenerate triangles, axis-parallel
// rays, origins on split planes), and watertightness on closed meshes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "kdtree/sah_builder.h"
#include "layout/dfl_layout.h"
#include "test_geometry.h"
#include "traversal/traversal.h"

namespace rtusim {
namespace {

using testing::add_grid_box;
using testing::add_icosphere;
using testing::random_soup;

Hit brute_force(const Scene& s, const Ray& ray, bool any_hit) {
  const WatertightRay wr(ray.origin, ray.dir);
  Hit best;
  best.t = ray.t_max;
  for (uint32_t i = 0; i < s.triangle_count(); ++i) {
    const auto v = s.vertices(i);
    float t, u, w;
    if (intersect_watertight(wr, v[0], v[1], v[2], best.t, t, u, w)) {
      best = {t, i, u, w};
      if (any_hit) break;
    }
  }
  if (!best.valid()) best.t = std::numeric_limits<float>::infinity();
  return best;
}

struct Fixture {
  Scene scene;
  KdTree tree;
  MemoryImage image;
  explicit Fixture(Scene s) : scene(std::move(s)) {
    tree = build_sah_kd_tree(scene, KdBuildParams{});
    image = DflLayout().build_image(tree, scene);
  }
  Hit kd(const Ray& r, bool any_hit) const {
    NullFetchSink sink;
    return traverse<DflLayout>(image, r, any_hit, sink);
  }
};

// Split planes of the tree, to start rays exactly on them.
std::vector<std::pair<int, float>> split_planes(const KdTree& tree) {
  std::vector<std::pair<int, float>> planes;
  for (const KdNode& n : tree.nodes)
    if (!n.is_leaf()) planes.emplace_back(n.axis, n.split);
  return planes;
}

void expect_same(const Fixture& f, const Ray& ray, int& hits, const char* what) {
  const Hit a = f.kd(ray, false), b = brute_force(f.scene, ray, false);
  ASSERT_EQ(a.valid(), b.valid()) << what << " o=" << ray.origin.x << "," << ray.origin.y << ","
                                  << ray.origin.z << " d=" << ray.dir.x << "," << ray.dir.y
                                  << "," << ray.dir.z;
  if (a.valid()) {
    ++hits;
    EXPECT_EQ(a.t, b.t) << what;  // same triangle test, so the closest t is bit-identical
  }
  // Any-hit: hit whenever something lies in (0, t_max).
  Ray bounded = ray;
  bounded.t_max = b.valid() ? b.t * 1.5f : 2.0f;
  EXPECT_EQ(f.kd(bounded, true).valid(), brute_force(f.scene, bounded, true).valid()) << what;
}

TEST(Traversal, MatchesBruteForceOnRandomSoups) {
  for (uint32_t seed : {1u, 2u, 3u}) {
    const Fixture f(random_soup(seed, 3000));
    std::mt19937 rng(seed * 77);
    std::uniform_real_distribution<float> u(-1.5f, 1.5f);
    int hits = 0;
    for (int i = 0; i < 3000; ++i) {
      Ray r;
      r.origin = {u(rng), u(rng), u(rng)};
      r.dir = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(1e-3f));
      expect_same(f, r, hits, "random");
    }
    EXPECT_GT(hits, 500) << "the test must exercise hits";
  }
}

TEST(Traversal, AxisParallelRaysAndOriginsOnSplitPlanes) {
  const Fixture f(random_soup(9, 3000));
  const auto planes = split_planes(f.tree);
  ASSERT_FALSE(planes.empty());
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.2f, 1.2f);
  std::uniform_int_distribution<size_t> pick(0, planes.size() - 1);
  std::uniform_int_distribution<int> ax(0, 2), sign(0, 1);
  int hits = 0;
  for (int i = 0; i < 4000; ++i) {
    Ray r;
    r.origin = {u(rng), u(rng), u(rng)};
    // Origin exactly on a split plane of the tree.
    const auto [pa, pv] = planes[pick(rng)];
    r.origin[pa] = pv;
    if (i % 2 == 0) {
      // Axis-parallel: along one axis, possibly lying in the plane.
      r.dir = glm::vec3(0.0f);
      r.dir[ax(rng)] = sign(rng) ? 1.0f : -1.0f;
    } else {
      r.dir = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(1e-3f));
      if (i % 4 == 1) r.dir[pa] = 0.0f;  // parallel to the plane it starts on
      r.dir = glm::normalize(r.dir);
    }
    expect_same(f, r, hits, "plane/parallel");
  }
  EXPECT_GT(hits, 300);
}

TEST(Traversal, DegenerateScenes) {
  // One triangle; all triangles identical; everything in one plane.
  Scene one;
  testing::add_triangle(one, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  testing::finish(one);
  Scene same;
  for (int i = 0; i < 200; ++i) testing::add_triangle(same, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  testing::finish(same);
  Scene flat = random_soup(4, 500);
  for (auto& p : flat.positions) p.z = 0.25f;
  for (const Scene* s : {&one, &same, &flat}) {
    const Fixture f(*s);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    int hits = 0;
    for (int i = 0; i < 500; ++i) {
      Ray r;
      r.origin = {u(rng) * 0.5f + 0.25f, u(rng) * 0.5f + 0.25f, 2.0f};
      r.dir = glm::normalize(glm::vec3(u(rng) * 0.2f, u(rng) * 0.2f, -1.0f));
      expect_same(f, r, hits, "degenerate");
    }
    EXPECT_GT(hits, 50);
  }
}

TEST(Traversal, EmptySceneMissesEverything) {
  Scene empty;
  testing::finish(empty);
  const Fixture f(empty);
  Ray r;
  r.origin = {0, 0, -1};
  r.dir = {0, 0, 1};
  EXPECT_FALSE(f.kd(r, false).valid());
}

// Rays from inside a closed mesh aimed exactly at its vertices and edge midpoints: the
// watertight test and the traversal must never let one through.
TEST(Traversal, WatertightOnClosedMeshes) {
  for (int mesh = 0; mesh < 2; ++mesh) {
    Scene s;
    if (mesh == 0) add_icosphere(s, {0.1f, 0.2f, 0.3f}, 1.0f, 3);
    else add_grid_box(s, {-1.0f, -0.5f, -0.25f}, {1.0f, 0.5f, 0.75f}, 8);
    testing::finish(s);
    const Fixture f(s);
    std::vector<glm::vec3> targets(s.positions.begin(), s.positions.end());
    for (const auto& t : s.triangles)
      for (int e = 0; e < 3; ++e)
        targets.push_back(0.5f * (s.positions[t[e]] + s.positions[t[(e + 1) % 3]]));
    const glm::vec3 inside = mesh == 0 ? glm::vec3(0.1f, 0.2f, 0.3f) : glm::vec3(0.0f, 0.0f, 0.25f);
    const std::vector<glm::vec3> origins = {inside, inside + glm::vec3(0.13f, -0.07f, 0.05f)};
    int leaks_kd = 0, leaks_bf = 0;
    for (const auto& o : origins)
      for (const auto& target : targets) {
        Ray r;
        r.origin = o;
        r.dir = target - o;  // not normalised: the exact direction to the vertex or edge
        leaks_kd += !f.kd(r, false).valid();
        leaks_bf += !brute_force(s, r, false).valid();
      }
    EXPECT_EQ(leaks_bf, 0) << "mesh " << mesh;
    EXPECT_EQ(leaks_kd, 0) << "mesh " << mesh;
  }
}

TEST(Traversal, ReportsFetchesInIssueOrder) {
  const Fixture f(random_soup(11, 2000));
  struct Recorder {
    std::vector<std::pair<Stream, uint64_t>> log;
    void fetch(Stream s, uint64_t a, uint32_t) { log.emplace_back(s, a); }
  } rec;
  Ray r;
  r.origin = {-2.0f, 0.05f, 0.03f};
  r.dir = {1.0f, 0.0f, 0.0f};
  const Hit h = traverse<DflLayout>(f.image, r, false, rec);
  ASSERT_FALSE(rec.log.empty());
  EXPECT_EQ(rec.log.front().first, Stream::kNode);
  EXPECT_EQ(rec.log.front().second, f.image.root_addr);
  for (const auto& [stream, addr] : rec.log) {
    const Region& reg = stream == Stream::kNode   ? f.image.nodes
                        : stream == Stream::kList ? f.image.lists
                                                  : f.image.triangles;
    EXPECT_GE(addr, reg.base_addr);
    EXPECT_LT(addr, reg.end_addr());
  }
  if (h.valid()) {
    // The hit triangle was fetched.
    const uint64_t ta = f.image.triangle_addr(h.triangle);
    EXPECT_TRUE(std::any_of(rec.log.begin(), rec.log.end(),
                            [&](const auto& e) { return e.second == ta; }));
  }
}

// The origin's side test's nudge: the float just below, as std::nextafter gives it, for zeros,
// infinities, NaN, subnormals and random floats of every magnitude and sign.
TEST(Traversal, NextFloatDownIsNextafterTowardMinusInfinity) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  std::vector<float> xs = {0.0f, -0.0f, kInf, -kInf, std::numeric_limits<float>::denorm_min(),
                           -std::numeric_limits<float>::denorm_min(),
                           std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
                           std::numeric_limits<float>::min(), -std::numeric_limits<float>::min()};
  std::mt19937 rng(5);
  for (int i = 0; i < 100000; ++i) {
    const uint32_t b = rng();
    float x;
    std::memcpy(&x, &b, sizeof x);
    xs.push_back(x);
  }
  for (const float x : xs) {
    const float got = next_float_down(x), want = std::nextafter(x, -kInf);
    if (std::isnan(x)) {
      EXPECT_TRUE(std::isnan(got));
    } else {
      EXPECT_EQ(std::memcmp(&got, &want, sizeof got), 0) << x;
    }
  }
}

// traversal_begin's per-axis setup (three lanes at once where SSE4.1 is there) against its
// scalar definition, for origins and directions at zero, infinity, NaN, subnormals and random
// floats: 1/direction, its magnitude, the side-test origin and the clipped interval.
TEST(Traversal, RaySetupEqualsItsScalarDefinition) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const std::vector<float> special = {0.0f, -0.0f, kInf, -kInf, std::nanf(""), 1e-40f, -1e-40f,
                                      1.0f, -1.0f, 3.5f, -0.25f, 1e30f, -1e30f};
  MemoryImage image;
  for (int a = 0; a < 3; ++a) image.bounds_min[a] = -2.0f, image.bounds_max[a] = 3.0f;
  std::mt19937 rng(7);
  std::uniform_int_distribution<size_t> pick(0, special.size() - 1);
  std::uniform_real_distribution<float> u(-4.0f, 4.0f);
  const auto same = [](float x, float y) {
    return std::memcmp(&x, &y, sizeof x) == 0 || (std::isnan(x) && std::isnan(y));
  };
  for (int i = 0; i < 20000; ++i) {
    Ray ray;
    for (int a = 0; a < 3; ++a) {
      ray.origin[a] = rng() % 3 ? u(rng) : special[pick(rng)];
      ray.dir[a] = rng() % 3 ? u(rng) : special[pick(rng)];
    }
    ray.t_max = 10.0f;
    TraversalState s;
    traversal_begin(s, image, ray, false);
    float t0 = 0.0f, t1 = ray.t_max;
    for (int a = 0; a < 3; ++a) {
      const float o = ray.origin[a], d = ray.dir[a], inv = 1.0f / d;
      EXPECT_TRUE(same(s.inv_dir[a], inv)) << i;
      EXPECT_TRUE(same(s.abs_inv_dir[a], std::abs(inv))) << i;
      EXPECT_TRUE(same(s.org_side[a], d <= 0.0f ? next_float_down(o) : o)) << i;
      if (d == 0.0f) {
        if (o < image.bounds_min[a] || o > image.bounds_max[a]) t1 = -1.0f;
        continue;
      }
      float tn = (image.bounds_min[a] - o) * inv, tf = (image.bounds_max[a] - o) * inv;
      if (tn > tf) std::swap(tn, tf);
      t0 = std::max(t0, tn * (1.0f - 6.0f * std::numeric_limits<float>::epsilon()));
      t1 = std::min(t1, tf * (1.0f + 6.0f * std::numeric_limits<float>::epsilon()));
    }
    EXPECT_TRUE(same(s.t_min, t0)) << i;
    EXPECT_TRUE(same(s.t_max, t1)) << i;
  }
}

}  // namespace
}  // namespace rtusim
