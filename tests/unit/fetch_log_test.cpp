// FetchLog: the recorded fetches come back exactly, in order, with their rays, one word a fetch.
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
  std::vector<uint64_t> direct;  // each ray's counted DRAM bytes
  void end_ray(uint32_t pixel, RayKind kind, uint64_t direct_bytes) {
    rays.emplace_back(pixel, kind);
    ray_ends.push_back(fetches.size());
    direct.push_back(direct_bytes);
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

TEST(FetchLogTest, OneWordPerFetchAndClearRestarts) {
  FetchLog log;
  RayRecord r;
  for (int i = 0; i < 1000; ++i) log.fetch(Stream::kNode, 1u << 20 | (i % 16) * 8, 8);
  log.end_ray(r);
  const size_t one_ray = log.size_bytes() - 1000 * sizeof(uint64_t);
  log.clear();
  EXPECT_EQ(log.ray_count(), 0u);
  EXPECT_EQ(log.size_bytes(), 0u);
  // A fetch past the short form (an address at 2^40, a size at 2^22) takes three words.
  log.fetch(Stream::kList, 64, 12);
  log.fetch(Stream::kTriangle, uint64_t{1} << 40, 36);
  log.fetch(Stream::kNode, 128, 1u << 22);
  log.end_ray(r);
  EXPECT_EQ(log.size_bytes(), 7 * sizeof(uint64_t) + one_ray);
  Collector c;
  log.replay(c);
  ASSERT_EQ(c.fetches.size(), 3u);
  EXPECT_EQ(c.fetches[0], Fetch(1, 64, 12));
  EXPECT_EQ(c.fetches[1], Fetch(2, uint64_t{1} << 40, 36));
  EXPECT_EQ(c.fetches[2], Fetch(0, 128, 1u << 22));
}

// With the backend's needs set, repeated node hits and straight-to-DRAM fetches are counted
// while recording, the rest logged as before; clear() restarts the counting.
TEST(FetchLogTest, CountsWhatTheReplayDoesNotNeed) {
  FetchLog log;
  log.set_needs({.node_line_bytes = 64, .lists_triangles_direct = true});
  RayRecord a, b;
  a.pixel = 1;
  b.pixel = 2;
  log.fetch(Stream::kNode, 128, 8);       // logged: the first of its line
  log.fetch(Stream::kNode, 136, 8);       // counted: the same line
  log.fetch(Stream::kList, 60, 8);        // counted: two bursts (60..67)
  log.fetch(Stream::kNode, 184, 16);      // logged: ends in the next line (128..191, 192..199)
  log.fetch(Stream::kNode, 192, 8);       // counted: the line the previous fetch ended in
  log.fetch(Stream::kNode, 180, 4);       // logged: line 128 again, but not the last one
  log.fetch(Stream::kNode, 0, 0);         // logged: no access
  log.end_ray(a);
  log.fetch(Stream::kNode, 188, 4);       // counted: across rays too
  log.fetch(Stream::kTriangle, 64, 36);   // counted: one burst
  log.fetch(Stream::kTriangle, 100, 36);  // counted: two bursts (100..135)
  log.end_ray(b);
  EXPECT_EQ(log.counted_node_hits(), 3u);
  EXPECT_EQ(log.direct_counts()[1].fetches, 1u);
  EXPECT_EQ(log.direct_counts()[1].bursts, 2u);
  EXPECT_EQ(log.direct_counts()[2].fetches, 2u);
  EXPECT_EQ(log.direct_counts()[2].bursts, 3u);
  Collector c;
  log.replay(c);
  EXPECT_EQ(c.fetches, (std::vector<Fetch>{{0, 128, 8}, {0, 184, 16}, {0, 180, 4}, {0, 0, 0}}));
  EXPECT_EQ(c.ray_ends, (std::vector<size_t>{4, 4}));
  EXPECT_EQ(c.direct, (std::vector<uint64_t>{128, 192}));
  log.clear();
  EXPECT_EQ(log.counted_node_hits(), 0u);
  EXPECT_EQ(log.direct_counts()[2].fetches, 0u);
  log.fetch(Stream::kNode, 188, 4);  // logged: the first after clear()
  log.end_ray(a);
  EXPECT_EQ(log.counted_node_hits(), 0u);
  EXPECT_GT(log.size_bytes(), 0u);
}

}  // namespace
}  // namespace rtusim
