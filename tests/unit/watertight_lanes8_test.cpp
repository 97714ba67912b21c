// The 8-lane watertight test (one triangle against 8 rays) against the single-ray test, bit for
// bit, lane by lane: rays of every axis permutation side by side, random lanes left out, a limit
// of each lane's own; random triangles, and coarse ones that share edges and vertices (zero
// barycentrics) with origins on their planes (t to refine), which must go to the single-ray
// code or match it.
#include "traversal/watertight_lanes8.h"

#include <array>
#include <bit>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "test_geometry.h"
#include "traversal/watertight_triangle.h"

namespace rtusim {
namespace {

#if defined(__AVX2__)

uint32_t bits(float f) { return std::bit_cast<uint32_t>(f); }

struct Counts {
  int hits = 0, misses = 0, scalar = 0, left_out = 0;
  uint32_t permutations = 0;  // bit kz * 2 + (kx > ky): permutations seen
};

// `rounds` triangles, each against 8 lanes of rays from `make_ray(rng, v, lane, o, d)`.
template <class MakeRay>
Counts compare_rounds(uint32_t seed, int rounds, bool coarse, MakeRay make_ray,
                      float scale = 1.0f) {
  std::mt19937 rng(seed);
  Counts n;
  for (int round = 0; round < rounds; ++round) {
    // The triangle's nine floats with a guard float after them (the test reads floats 1..8 as
    // one 8-float load: nothing past the ninth).
    alignas(32) std::array<float, 10> v{};
    for (int i = 0; i < 9; ++i) v[i] = scale * testing::random_coordinate(rng, coarse);
    if (round % 5 == 0) v[3 + rng() % 6] = v[rng() % 3];  // a degenerate (or sliver) member
    v[9] = std::numeric_limits<float>::quiet_NaN();
    WatertightLanes8 lanes;
    WatertightRay rays[8];
    alignas(32) float t_max[8];
    alignas(32) int32_t todo_bits[8];
    for (int lane = 0; lane < 8; ++lane) {
      float o[3], d[3];
      make_ray(rng, v.data(), lane, o, d);
      rays[lane] = WatertightRay(glm::vec3(o[0], o[1], o[2]), glm::vec3(d[0], d[1], d[2]));
      lanes.set_lane(lane, rays[lane]);
      n.permutations |= 1u << (rays[lane].kz * 2 + (rays[lane].kx > rays[lane].ky));
      t_max[lane] = rng() % 3 == 0 ? std::numeric_limits<float>::infinity()
                                   : scale * std::uniform_real_distribution<float>(0.0f, 16.0f)(rng);
      todo_bits[lane] = rng() % 6 == 0 ? 0 : -1;
    }
    const WatertightLanes8::Outcome o = lanes.test(
        reinterpret_cast<const uint8_t*>(v.data()),
        _mm256_castsi256_ps(_mm256_load_si256(reinterpret_cast<const __m256i*>(todo_bits))),
        _mm256_load_ps(t_max));
    alignas(32) float hit[8], scalar[8], t[8], bu[8], bv[8];
    _mm256_store_ps(hit, o.hit);
    _mm256_store_ps(scalar, o.scalar);
    _mm256_store_ps(t, o.t);
    _mm256_store_ps(bu, o.u);
    _mm256_store_ps(bv, o.v);
    for (int lane = 0; lane < 8; ++lane) {
      const bool lane_hit = bits(hit[lane]) != 0, lane_scalar = bits(scalar[lane]) != 0;
      if (todo_bits[lane] == 0) {
        ++n.left_out;
        EXPECT_FALSE(lane_hit || lane_scalar) << "round " << round << " lane " << lane;
        continue;
      }
      if (lane_scalar) {
        ++n.scalar;
        EXPECT_FALSE(lane_hit) << "round " << round << " lane " << lane;
        continue;
      }
      float t0 = 0, u0 = 0, v0 = 0;
      const bool want = intersect_watertight(rays[lane], v.data(), t_max[lane], t0, u0, v0);
      EXPECT_EQ(lane_hit, want) << "round " << round << " lane " << lane;
      if (lane_hit != want) return n;
      if (want) {
        EXPECT_EQ(bits(t[lane]), bits(t0)) << "round " << round << " lane " << lane;
        EXPECT_EQ(bits(bu[lane]), bits(u0)) << "round " << round << " lane " << lane;
        EXPECT_EQ(bits(bv[lane]), bits(v0)) << "round " << round << " lane " << lane;
      }
      ++(want ? n.hits : n.misses);
    }
  }
  return n;
}

TEST(WatertightLanes8, RandomRaysMatchTheSingleRayTestBitForBit) {
  // Rays from around the triangle towards it, each lane its own direction (so its own axis
  // permutation and winding swap).
  const Counts n = compare_rounds(21, 20000, false, [](std::mt19937& rng, const float* v, int,
                                                       float* o, float* d) {
    float target[3];
    const float a = std::uniform_real_distribution<float>(-0.2f, 0.8f)(rng);
    const float b = std::uniform_real_distribution<float>(-0.2f, 0.8f)(rng);
    for (int k = 0; k < 3; ++k) {
      target[k] = v[k] + a * (v[3 + k] - v[k]) + b * (v[6 + k] - v[k]);
      o[k] = testing::random_coordinate(rng, false) * 3.0f;
      d[k] = target[k] - o[k];
    }
  });
  EXPECT_GT(n.hits, 20000);
  EXPECT_GT(n.misses, 20000);
  EXPECT_GT(n.left_out, 10000);
  EXPECT_EQ(n.permutations, 0x3fu);  // all six permutations (three axes, both windings)
}

TEST(WatertightLanes8, EdgeAndPlaneCasesGoToTheSingleRayTestOrMatchIt) {
  // Coarse triangles, rays with small integer directions from coarse origins: exact
  // arithmetic, so rays through edges and vertices give zero barycentrics; some origins on a
  // vertex (t = 0, refined).
  const Counts n = compare_rounds(22, 20000, true, [](std::mt19937& rng, const float* v, int lane,
                                                      float* o, float* d) {
    const int corner = static_cast<int>(rng() % 3);
    for (int k = 0; k < 3; ++k) {
      o[k] = lane % 3 == 0 ? v[3 * corner + k] : testing::random_coordinate(rng, true) * 2.0f;
      d[k] = static_cast<float>(static_cast<int>(rng() % 5) - 2);
    }
    if (d[0] == 0.0f && d[1] == 0.0f && d[2] == 0.0f) d[2] = 1.0f;
  });
  EXPECT_GT(n.hits, 500);
  EXPECT_GT(n.scalar, 1000);  // the rare paths were reached
}


TEST(WatertightLanes8, OverflowingLanesGoToTheSingleRayTestOrMatchIt) {
  // Coordinates of ~1e13: T = t det overflows float; such lanes are the single-ray code's.
  int hits = 0;
  for (const float scale : {3e12f, 1e13f, 1e14f}) {
    const Counts n = compare_rounds(23, 2000, false, [scale](std::mt19937& rng, const float* v,
                                                             int, float* o, float* d) {
      const float a = std::uniform_real_distribution<float>(0.1f, 0.4f)(rng);
      const float b = std::uniform_real_distribution<float>(0.1f, 0.4f)(rng);
      for (int k = 0; k < 3; ++k) {
        const float target = v[k] + a * (v[3 + k] - v[k]) + b * (v[6 + k] - v[k]);
        o[k] = scale * testing::random_coordinate(rng, false) * 3.0f;
        d[k] = (target - o[k]) / scale;
      }
    }, scale);
    EXPECT_GT(n.scalar, 1000) << "scale " << scale;
    hits += n.hits;
  }
  EXPECT_GT(hits, 1000);  // lanes that stayed in float and matched the single-ray test
  RecordProperty("float_hits", std::to_string(hits));
}

#else

TEST(WatertightLanes8, NeedsAvx2) { GTEST_SKIP() << "built without AVX2: no 8-lane test"; }

#endif

}  // namespace
}  // namespace rtusim
