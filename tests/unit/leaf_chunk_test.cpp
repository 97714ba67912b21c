// The 16-lane leaf test against the scalar watertight test, bit for bit: random triangles, fans
// of triangles sharing edges and vertices (zero barycentrics), origins on the triangles' planes
// (t to refine), and limits lowered after the chunk was tested (as a leaf's earlier hits do).
// Then the chunked leaf loop (detail::leaf_triangles_chunked) against the scalar one: the same
// hit, triangles tested, any-hit stop and fetches, in order.
#include "traversal/leaf_chunk_avx512.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "layout/memory_image.h"
#include "test_geometry.h"
#include "traversal/fetch_recorder.h"
#include "traversal/traversal.h"
#include "traversal/watertight_triangle.h"

namespace rtusim {
namespace {

#if defined(__AVX512F__)

uint32_t bits(float f) { return std::bit_cast<uint32_t>(f); }

// Triangles as the memory image stores them (nine floats each, from byte kBase) and a list of
// their ids, shuffled.
struct Triangles {
  static constexpr uint64_t kBase = 64;
  std::vector<uint8_t> bytes;
  std::vector<uint32_t> ids;
  std::array<float, 9> vertices(uint32_t id) const {
    std::array<float, 9> v;
    std::memcpy(v.data(), bytes.data() + kBase + 36ull * id, sizeof v);
    return v;
  }
};

Triangles random_triangles(std::mt19937& rng, int count, bool coarse) {
  Triangles tris;
  tris.bytes.assign(Triangles::kBase + 36ull * count, 0);
  for (int i = 0; i < count; ++i) {
    float v[9];
    for (float& x : v) x = testing::random_coordinate(rng, coarse);
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
      const std::array<float, 9> v = tris.vertices(tris.ids[base + i]);
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
      o[a] = testing::random_coordinate(rng, false) * 3.0f;
      d[a] = -o[a] * 0.25f + testing::random_coordinate(rng, false) * 0.1f;
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
    const std::array<float, 9> v = tris.vertices(tris.ids[rng() % tris.ids.size()]);
    for (int a = 0; a < 3; ++a) {
      o[a] = ray % 3 == 0 ? v[a] : testing::random_coordinate(rng, true) * 2.0f;
      d[a] = static_cast<float>(static_cast<int>(rng() % 5) - 2);
    }
    if (d[0] == 0.0f && d[1] == 0.0f && d[2] == 0.0f) d[2] = 1.0f;
    return 1e30f;
  });
  EXPECT_GT(n.hits, 100);
  EXPECT_GT(n.scalar, 100);  // the rare paths were reached
}

// A leaf holding `tris` in a memory image: their vertices at Triangles::kBase, the leaf's id
// list in its own region after them.
struct LeafImage {
  MemoryImage image;
  NodeView leaf;
};

LeafImage leaf_image(const Triangles& tris) {
  LeafImage l;
  MemoryImage& m = l.image;
  m.bytes = tris.bytes;
  m.triangles = {Triangles::kBase, 36ull * tris.ids.size()};
  m.lists = {align_region(m.triangles.end_addr()), 4ull * tris.ids.size()};
  m.bytes.resize(m.lists.end_addr());
  std::memcpy(m.bytes.data() + m.lists.base_addr, tris.ids.data(), m.lists.size_bytes);
  l.leaf.leaf = true;
  l.leaf.prim_count = static_cast<uint32_t>(tris.ids.size());
  l.leaf.list_addr = m.lists.base_addr;
  return l;
}

// The fetches a leaf loop reports, in order (a sink of this file's own, so the loops under test
// are instantiated here).
struct RecordedFetches {
  std::vector<RecordedFetch> fetches;
  void fetch(Stream s, uint64_t addr, uint32_t bytes) { fetches.push_back({s, addr, bytes}); }
};

// One ray into one leaf, starting from hit `prior`, through both leaf loops: the chunked one must
// leave the scalar one's hit (bit for bit), triangle count, done flag and fetch list.
::testing::AssertionResult leaf_loops_agree(const LeafImage& l, const WatertightRay& wray,
                                            const Hit& prior, float ray_t_max, bool any_hit,
                                            detail::LeafOutcome& out) {
  Hit hit = prior;  // the scalar loop's
  RecordedFetches want_sink, got_sink;
  const detail::LeafTested scalar =
      detail::leaf_triangles_loop(wray, hit, ray_t_max, any_hit, l.image, l.leaf, want_sink);
  out = detail::leaf_triangles_chunked(wray, prior, ray_t_max, any_hit, l.image, l.leaf,
                                       got_sink);
  const std::vector<RecordedFetch>& want = want_sink.fetches;
  const std::vector<RecordedFetch>& got = got_sink.fetches;
  auto fail = [&]() {
    return ::testing::AssertionFailure()
           << (any_hit ? "any-hit" : "closest-hit") << ", prior t " << prior.t << ", t_max "
           << ray_t_max << ", " << l.leaf.prim_count << " triangles: ";
  };
  if (bits(out.hit.t) != bits(hit.t) || out.hit.triangle != hit.triangle ||
      bits(out.hit.u) != bits(hit.u) || bits(out.hit.v) != bits(hit.v))
    return fail() << "hit t " << out.hit.t << " triangle " << out.hit.triangle << ", scalar t "
                  << hit.t << " triangle " << hit.triangle;
  if (out.tested != scalar.tested)
    return fail() << "tested " << out.tested << ", scalar " << scalar.tested;
  if (out.done != scalar.done) return fail() << "done " << out.done << ", scalar " << scalar.done;
  for (size_t k = 0; k < std::max(got.size(), want.size()); ++k) {
    if (k >= got.size() || k >= want.size())
      return fail() << got.size() << " fetches, scalar " << want.size();
    if (got[k].stream != want[k].stream || got[k].addr != want[k].addr ||
        got[k].bytes != want[k].bytes)
      return fail() << "fetch " << k << " at " << got[k].addr << ", scalar at " << want[k].addr;
  }
  return ::testing::AssertionSuccess();
}

TEST(LeafChunkTest, ChunkedLeafLoopMatchesTheScalarLoop) {
  std::mt19937 rng(13);
  constexpr uint32_t kPriorTriangle = 1u << 30;  // a hit found before the leaf, in no chunk
  int found = 0, kept_prior = 0, stopped_early = 0, hits_in_two_chunks = 0;
  for (int round = 0; round < 300; ++round) {
    const bool coarse = round % 2 == 1;
    const Triangles tris = random_triangles(rng, 4 + static_cast<int>(rng() % 37), coarse);
    const LeafImage l = leaf_image(tris);
    for (int ray = 0; ray < 20; ++ray) {
      float o[3], d[3];
      for (int a = 0; a < 3; ++a) {
        o[a] = testing::random_coordinate(rng, coarse) * 3.0f;
        d[a] = coarse ? static_cast<float>(static_cast<int>(rng() % 5) - 2)
                      : -o[a] * 0.25f + testing::random_coordinate(rng, false) * 0.1f;
      }
      if (d[0] == 0.0f && d[1] == 0.0f && d[2] == 0.0f) d[2] = 1.0f;
      const WatertightRay wray(glm::vec3(o[0], o[1], o[2]), glm::vec3(d[0], d[1], d[2]));
      // Every triangle's own hit distance, in leaf order, to choose limits among them.
      std::vector<float> ts;
      uint32_t hit_chunks = 0;  // bit c: chunk c holds a hit
      for (size_t i = 0; i < tris.ids.size(); ++i) {
        float t, bu, bv;
        if (intersect_watertight(wray, tris.vertices(tris.ids[i]), 1e30f, t, bu, bv)) {
          ts.push_back(t);
          hit_chunks |= 1u << (i / LeafChunk::kLanes);
        }
      }
      auto some_t = [&]() { return ts.empty() ? 1.0f : ts[rng() % ts.size()]; };
      // A hit found before the leaf: none, at one triangle's t (a tie), halfway to one, or
      // nearer than all; the ray's own limit: none, at one triangle's t, or below one.
      Hit prior;
      switch (ray % 4) {
        case 1: prior.t = some_t(); break;
        case 2: prior.t = some_t() * 0.5f; break;
        case 3: prior.t = 1e-3f; break;
        default: break;
      }
      if (ray % 4 != 0) prior = {prior.t, kPriorTriangle, 0.25f, 0.5f};
      const float ray_t_max = ray % 3 == 0 ? std::numeric_limits<float>::infinity()
                              : ray % 3 == 1 ? some_t()
                                             : some_t() * 0.75f;
      for (const bool any_hit : {false, true}) {
        detail::LeafOutcome out;
        ASSERT_TRUE(leaf_loops_agree(l, wray, prior, ray_t_max, any_hit, out))
            << "round " << round << " ray " << ray;
        found += out.hit.triangle != prior.triangle;
        kept_prior += prior.valid() && !ts.empty() && out.hit.triangle == kPriorTriangle;
        stopped_early += out.done && out.tested < l.leaf.prim_count;
        hits_in_two_chunks += !any_hit && !prior.valid() && (hit_chunks & (hit_chunks - 1)) != 0;
      }
    }
  }
  // The merge's cases were all reached: hits found, hits kept from before the leaf, any-hit
  // stops inside the leaf, and hits in two or more chunks of one leaf.
  EXPECT_GT(found, 1000);
  EXPECT_GT(kept_prior, 2000);
  EXPECT_GT(stopped_early, 400);
  EXPECT_GT(hits_in_two_chunks, 200);
}

#else

TEST(LeafChunkTest, NeedsAvx512) {
  GTEST_SKIP() << "built without AVX-512: the leaf test is scalar";
}

#endif

}  // namespace
}  // namespace rtusim
