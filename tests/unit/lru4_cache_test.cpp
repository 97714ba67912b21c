// Lru4Cache (recency-ordered 4-way LRU, the replay's form of the default L1) against
// BasicSetAssocCache<LruPolicy> with 4 ways: the same hit or miss on every access, for single-line
// replays and line ranges, over caches from one set to many and line sizes 4 to 256 bytes.
#include "cache/lru4_cache.h"

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "cache/set_assoc_cache.h"

namespace rtusim {
namespace {

TEST(Lru4CacheTest, SameHitsAndMissesAsTheTimeStampedLru) {
  std::mt19937_64 rng(11);
  for (const uint32_t line : {4u, 64u, 256u}) {
    for (const uint64_t sets : {1u, 2u, 32u, 1024u}) {
      CacheParams p;
      p.line_bytes = line;
      p.assoc = 4;
      p.size_bytes = sets * 4 * line;
      ASSERT_TRUE(Lru4Cache::fits(p));
      Lru4Cache got(p);
      BasicSetAssocCache<LruPolicy> want(p);
      // Addresses over 3x the cache's lines (hits, misses and evictions in every set), with
      // runs of the same line and a hot region.
      const uint64_t span = p.size_bytes * 3;
      for (int chunk = 0; chunk < 400; ++chunk) {
        std::vector<uint64_t> addrs(rng() % 64 + 1);
        for (size_t i = 0; i < addrs.size(); ++i) {
          addrs[i] = rng() % 4 == 0 ? rng() % (p.size_bytes / 2) : rng() % span;
          if (i > 0 && rng() % 8 == 0) addrs[i] = addrs[i - 1] + rng() % line;  // near the last
        }
        if (chunk % 3 == 0) {
          for (const uint64_t a : addrs) {
            const uint32_t bytes = static_cast<uint32_t>(rng() % (3 * line));
            ASSERT_EQ(got.access_range(a, bytes), want.access_range(a, bytes))
                << "line " << line << " sets " << sets << " chunk " << chunk;
          }
        } else {
          uint64_t want_missed = 0;
          for (const uint64_t a : addrs) want_missed += want.access(a) ? 0 : 1;
          ASSERT_EQ(got.replay(addrs), want_missed)
              << "line " << line << " sets " << sets << " chunk " << chunk;
        }
        ASSERT_EQ(got.accesses(), want.accesses());
        ASSERT_EQ(got.misses(), want.misses());
      }
      EXPECT_GT(got.misses(), 0u);
      EXPECT_GT(got.accesses() - got.misses(), 0u);
      EXPECT_EQ(got.bytes_from_dram(), want.bytes_from_dram());
    }
  }
}

TEST(Lru4CacheTest, FitsOnlyFourWayLru) {
  CacheParams p;
  EXPECT_TRUE(Lru4Cache::fits(p));
  p.policy = "tree-plru";
  EXPECT_FALSE(Lru4Cache::fits(p));
  p.policy = "lru";
  p.assoc = 8;
  EXPECT_FALSE(Lru4Cache::fits(p));
}

}  // namespace
}  // namespace rtusim
