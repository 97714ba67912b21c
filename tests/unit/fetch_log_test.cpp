// FetchLog: the recorded fetches come back exactly, in order, with their rays, and compactly.
#include "tracer/fetch_log.h"

#include <random>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

namespace rtusim {
namespace {

using Fetch = std::tuple<int, uint64_t, uint32_t>;  // stream, address, bytes

// Collects what a replay hands out.
struct Collector {
  std::vector<Fetch> fetches;
  std::vector<std::pair<uint32_t, RayKind>> rays;
  std::vector<size_t> ray_ends;  // fetch count at each end_ray
  void fetch(Stream s, uint64_t addr, uint32_t bytes) {
    fetches.emplace_back(static_cast<int>(s), addr, bytes);
  }
  void end_ray(uint32_t pixel, RayKind kind) {
    rays.emplace_back(pixel, kind);
    ray_ends.push_back(fetches.size());
  }
};

TEST(FetchLogTest, ReplaysEveryFetchInOrderWithItsRay) {
  std::mt19937_64 rng(7);
  FetchLog log;
  std::vector<Fetch> expected;
  std::vector<size_t> ends;
  std::vector<std::pair<uint32_t, RayKind>> rays;
  for (uint32_t ray = 0; ray < 200; ++ray) {
    const int n = static_cast<int>(rng() % 40);  // some rays fetch nothing
    for (int i = 0; i < n; ++i) {
      const int s = static_cast<int>(rng() % 3);
      // Near and far steps both ways, the extremes of the address range, zero-byte fetches.
      uint64_t addr = rng() % 4 == 0 ? rng() : 4096 + (rng() % 512) * 8;
      if (i == 5) addr = ~uint64_t{0};
      if (i == 6) addr = 0;
      const uint32_t bytes = rng() % 5 == 0 ? static_cast<uint32_t>(rng() % 300) : 8;
      log.fetch(static_cast<Stream>(s), addr, bytes);
      expected.emplace_back(s, addr, bytes);
    }
    RayRecord r;
    r.pixel = ray * 3;
    r.kind = static_cast<RayKind>(ray % kRayKinds);
    log.end_ray(r);
    rays.emplace_back(r.pixel, r.kind);
    ends.push_back(expected.size());
  }
  Collector c;
  log.replay(c);
  EXPECT_EQ(c.fetches, expected);
  EXPECT_EQ(c.rays, rays);
  EXPECT_EQ(c.ray_ends, ends);
  EXPECT_EQ(log.ray_count(), 200u);
  EXPECT_EQ(log.ray_count(RayKind::kShadow), 50u);
}

TEST(FetchLogTest, NearbyFetchesTakeFewBytesAndClearRestarts) {
  FetchLog log;
  RayRecord r;
  for (int i = 0; i < 1000; ++i) log.fetch(Stream::kNode, 1u << 20 | (i % 16) * 8, 8);
  log.end_ray(r);
  EXPECT_LT(log.size_bytes(), 1000u * 3);  // tag + a one- or two-byte step
  log.clear();
  EXPECT_EQ(log.ray_count(), 0u);
  log.fetch(Stream::kList, 64, 12);
  log.end_ray(r);
  Collector c;
  log.replay(c);
  ASSERT_EQ(c.fetches.size(), 1u);
  EXPECT_EQ(c.fetches[0], Fetch(1, 64, 12));
}

}  // namespace
}  // namespace rtusim
