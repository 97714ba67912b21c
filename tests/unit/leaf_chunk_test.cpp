// The 16-lane leaf test against the scalar watertight test, bit for bit: random triangles, fans
// of triangles sharing edges and vertices (zero barycentrics), origins on the triangles' planes
// (t to refine), and limits lowered after the chunk was tested (as a leaf's earlier hits do).
#include "traversal/leaf_chunk_avx512.h"

#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "traversal/watertight_triangle.h"

namespace rtusim {
namespace {

#if defined(__AVX512F__)

uint32_t bits(float f) {
  uint32_t b;
  std::memcpy(&b, &f, sizeof b);
  return b;
}

// Triangles as the memory image stores them (nine floats each, from byte kBase) and a list of
// their ids, shuffled.
struct Triangles {
  static constexpr uint64_t kBase = 64;
  std::vector<uint8_t> bytes;
  std::vector<uint32_t> ids;
  const float* vertices(uint32_t id) const {
    return reinterpret_cast<const float*>(bytes.data() + kBase + 36ull * id);
  }
};

// A coarse coordinate (multiples of 1/8 in [-4, 4]): fans of such triangles share exact edges
// and vertices, and rays through them meet zero barycentrics; else a fine random one.
float coordinate(std::mt19937& rng, bool coarse) {
  if (coarse) return static_cast<float>(static_cast<int>(rng() % 65) - 32) / 8.0f;
  return std::uniform_real_distribution<float>(-4.0f, 4.0f)(rng);
}

Triangles random_triangles(std::mt19937& rng, int count, bool coarse) {
  Triangles tris;
  tris.bytes.assign(Triangles::kBase + 36ull * count, 0);
  for (int i = 0; i < count; ++i) {
    float v[9];
    for (float& x : v) x = coordinate(rng, coarse);
    std::memcpy(tris.bytes.data() + Triangles::kBase + 36ull * i, v, sizeof v);
    tris.ids.push_back(static_cast<uint32_t>(i));
  }
  std::shuffle(tris.ids.begin(), tris.ids.end(), rng);
  return tris;
}

struct Counts {
  int hits = 0, scalar = 0, misses = 0;
};

// Tests every chunk of `tris` against ray o + t d with the 16-lane test and compares each lane,
// at the chunk's limit and at lower ones, with the scalar test.
void compare(const Triangles& tris, const float* o, const float* d, float t_limit, Counts& n) {
  const WatertightRay r(glm::vec3(o[0], o[1], o[2]), glm::vec3(d[0], d[1], d[2]));
  for (size_t base = 0; base < tris.ids.size(); base += LeafChunk::kLanes) {
    const int lanes = static_cast<int>(std::min<size_t>(LeafChunk::kLanes, tris.ids.size() - base));
    LeafChunk c;
    c.test(r, tris.bytes.data(), Triangles::kBase,
           reinterpret_cast<const uint8_t*>(tris.ids.data() + base), lanes, t_limit);
    EXPECT_EQ(c.hit_mask >> lanes, 0u);
    EXPECT_EQ(c.scalar_mask >> lanes, 0u);
    for (int i = 0; i < lanes; ++i) {
      const float* v = tris.vertices(tris.ids[base + i]);
      if (c.scalar_mask >> i & 1u) {
        ++n.scalar;
        continue;  // the leaf test hands it to the scalar test itself
      }
      for (const float limit : {t_limit, t_limit * 0.5f, t_limit * 0.01f}) {
        float t0 = 0, u0 = 0, v0 = 0, t1 = 0, u1 = 0, v1 = 0;
        const bool scalar_hit = intersect_watertight(r, v, limit, t0, u0, v0);
        const bool lane_hit = (c.hit_mask >> i & 1u) && c.accept(i, limit, t1, u1, v1);
        ASSERT_EQ(scalar_hit, lane_hit) << "lane " << i << " limit " << limit;
        if (scalar_hit) {
          EXPECT_EQ(bits(t0), bits(t1));
          EXPECT_EQ(bits(u0), bits(u1));
          EXPECT_EQ(bits(v0), bits(v1));
        }
        if (limit == t_limit) ++(scalar_hit ? n.hits : n.misses);
      }
    }
  }
}

// 300 leaves of 1..40 random triangles (coarse or fine coordinates), 20 rays each from
// `make_ray(rng, tris, ray, o, d)`, which returns the ray's limit.
template <class MakeRay>
Counts compare_rounds(uint32_t seed, bool coarse, MakeRay make_ray) {
  std::mt19937 rng(seed);
  Counts n;
  for (int round = 0; round < 300; ++round) {
    const Triangles tris = random_triangles(rng, 1 + static_cast<int>(rng() % 40), coarse);
    for (int ray = 0; ray < 20; ++ray) {
      float o[3], d[3];
      const float t_limit = make_ray(rng, tris, ray, o, d);
      compare(tris, o, d, t_limit, n);
    }
  }
  return n;
}

TEST(LeafChunkTest, RandomTrianglesMatchTheScalarTestBitForBit) {
  const Counts n = compare_rounds(11, false, [](std::mt19937& rng, const Triangles&, int ray,
                                                float* o, float* d) {
    for (int a = 0; a < 3; ++a) {
      o[a] = coordinate(rng, false) * 3.0f;
      d[a] = -o[a] * 0.25f + coordinate(rng, false) * 0.1f;
    }
    return ray % 2 ? 1e30f : 8.0f;
  });
  EXPECT_GT(n.hits, 1000);
  EXPECT_GT(n.misses, 1000);
}

TEST(LeafChunkTest, EdgeAndPlaneCasesGoToTheScalarTestOrMatchIt) {
  // Axis-aligned and coarse rays through shared edges; some origins on a triangle vertex.
  const Counts n = compare_rounds(12, true, [](std::mt19937& rng, const Triangles& tris, int ray,
                                               float* o, float* d) {
    const float* v = tris.vertices(tris.ids[rng() % tris.ids.size()]);
    for (int a = 0; a < 3; ++a) {
      o[a] = ray % 3 == 0 ? v[a] : coordinate(rng, true) * 2.0f;
      d[a] = static_cast<float>(static_cast<int>(rng() % 5) - 2);
    }
    if (d[0] == 0.0f && d[1] == 0.0f && d[2] == 0.0f) d[2] = 1.0f;
    return 1e30f;
  });
  EXPECT_GT(n.hits, 100);
  EXPECT_GT(n.scalar, 100);  // the rare paths were reached
}

#else

TEST(LeafChunkTest, NeedsAvx512) {
  GTEST_SKIP() << "built without AVX-512: the leaf test is scalar";
}

#endif

}  // namespace
}  // namespace rtusim
