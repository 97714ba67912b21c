// CacheSweep (one pass, every configuration) against one SetAssocCache per configuration over
// the same fetch stream: accesses and misses per stream tag must be equal for every policy,
// line size, set count and associativity, "full" (one set) included, with fetches straddling
// lines.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "cache/set_assoc_cache.h"
#include "sweep/cache_sweep.h"
#include "sweep/sweep_pipeline.h"

namespace rtusim {
namespace {

// A stream with locality: mostly near the last address, sometimes a jump, sometimes a revisit.
std::vector<SweepFetch> make_stream(uint64_t image_bytes, size_t n, uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<SweepFetch> out;
  std::vector<uint64_t> recent(64, 0);
  uint64_t addr = 0;
  for (size_t i = 0; i < n; ++i) {
    const uint32_t r = rng() % 100;
    if (r < 60) addr = (addr + rng() % 96) % (image_bytes - 64);
    else if (r < 85) addr = recent[rng() % recent.size()];
    else addr = rng() % (image_bytes - 64);
    recent[i % recent.size()] = addr;
    const uint32_t bytes = (i % 17 == 0) ? 0 : 4 + static_cast<uint32_t>(rng() % 37);
    out.push_back({addr, bytes, static_cast<uint32_t>(rng() % 3)});
  }
  return out;
}

// Every configuration of `policies` x lines 16, 32, 64 B x sizes 256 B .. 4 KB x `assocs` (0:
// full) that fits, in one pass (parts and threads of several kinds), against one cache each.
void expect_equal_to_one_cache_each(const std::vector<const char*>& policies,
                                    const std::vector<uint32_t>& assocs) {
  const uint64_t image_bytes = 1 << 16;
  std::vector<CacheParams> configs;
  for (const char* policy : policies)
    for (const uint32_t line : {16u, 32u, 64u})
      for (const uint64_t size : {256u, 1024u, 4096u})
        for (const uint32_t assoc : assocs) {
          CacheParams c;
          c.policy = policy;
          c.line_bytes = line;
          c.size_bytes = size;
          c.assoc = assoc ? assoc : static_cast<uint32_t>(size / line);
          c.seed = 7;
          if (size < uint64_t{line} * c.assoc) continue;
          configs.push_back(c);
        }
  const auto stream = make_stream(image_bytes, 200000, 1);
  CacheSweep sweep(configs, image_bytes, 3);  // set counts split in three parts per line
  sweep.set_threads(3);  // the groups and side caches shared out: the same counts
  CacheSweep whole(configs, image_bytes);  // one part per line: every set count in one walk
  CacheSweep piped(configs, image_bytes, 2);  // fed by a pipeline: tasks run ahead of each other
  CacheSweep pushed(configs, image_bytes, 2);  // a pipeline without workers: the pushing thread
  {
    SweepPipeline pipeline({&piped}, 3, 4), alone({&pushed}, 1, 4);
    SweepPipeline::Lists chunk(1), chunk_alone(1);
    for (size_t at = 0; at < stream.size(); at += 777) {  // uneven chunks
      const auto part = std::span(stream).subspan(at, std::min<size_t>(777, stream.size() - at));
      sweep.feed(part);
      whole.feed(part);
      for (const SweepFetch& f : part) {
        piped.record(chunk[0], f.addr(), f.bytes(), f.tag());
        pushed.record(chunk_alone[0], f.addr(), f.bytes(), f.tag());
      }
      pipeline.push(chunk);
      alone.push(chunk_alone);
    }
    pipeline.finish();
    alone.finish();
  }

  for (size_t i = 0; i < configs.size(); ++i) {
    SetAssocCache cache(configs[i]);
    CacheSweep::PerTag acc{}, miss{};
    for (const SweepFetch& f : stream) {
      const uint64_t before = cache.accesses();
      miss[f.tag()] += cache.access_range(f.addr(), f.bytes());
      acc[f.tag()] += cache.accesses() - before;
    }
    const CacheParams& c = configs[i];
    SCOPED_TRACE(c.policy + " " + std::to_string(c.size_bytes) + " B " + std::to_string(c.assoc) +
                 "-way " + std::to_string(c.line_bytes) + " B lines");
    EXPECT_EQ(sweep.accesses(i), acc);
    EXPECT_EQ(sweep.misses(i), miss);
    EXPECT_EQ(whole.accesses(i), acc);
    EXPECT_EQ(whole.misses(i), miss);
    EXPECT_EQ(piped.accesses(i), acc);
    EXPECT_EQ(piped.misses(i), miss);
    EXPECT_EQ(pushed.accesses(i), acc);
    EXPECT_EQ(pushed.misses(i), miss);
    EXPECT_GT(miss[0] + miss[1] + miss[2], 0u);
  }
}

TEST(CacheSweep, EqualsOneCachePerConfiguration) {
  // 16 ways: the set counts walked one SetLruStacks after the other.
  expect_equal_to_one_cache_each({"lru", "fifo", "tree-plru", "random"}, {1, 2, 4, 8, 16, 0});
}

TEST(CacheSweep, ShallowSetCountsWalkedInPairs) {
  // At most 8 ways: PairedSetStacks, with odd and even set-count counts per line and part.
  expect_equal_to_one_cache_each({"lru"}, {1, 2, 4, 8, 0});
  expect_equal_to_one_cache_each({"lru"}, {2, 8});
}

TEST(CacheSweep, OneSetStackAtManyCapacities) {
  // Fully associative LRU of 1 .. 64 lines over a cyclic scan of 40 lines: capacities below 40
  // miss every access, those of 40 and more only the first 40.
  std::vector<CacheParams> configs;
  for (const uint32_t lines : {1u, 2u, 8u, 32u, 64u}) {
    CacheParams c;
    c.line_bytes = 64;
    c.size_bytes = uint64_t{lines} * 64;
    c.assoc = lines;
    configs.push_back(c);
  }
  std::vector<SweepFetch> stream;
  for (int round = 0; round < 10; ++round)
    for (uint64_t line = 0; line < 40; ++line) stream.push_back({line * 64, 8, 0});
  CacheSweep sweep(configs, 40 * 64);
  sweep.feed(stream);
  for (size_t i = 0; i < configs.size(); ++i)
    EXPECT_EQ(sweep.misses(i)[0], configs[i].assoc >= 40 ? 40u : 400u) << configs[i].assoc;
}

TEST(SweepFetch, PacksItsFieldsAndRejectsWhatDoesNotFit) {
  const SweepFetch f((uint64_t{1} << 40) - 3, (1u << 22) - 1, 3);
  EXPECT_EQ(f.addr(), (uint64_t{1} << 40) - 3);
  EXPECT_EQ(f.bytes(), (1u << 22) - 1);
  EXPECT_EQ(f.tag(), 3u);
  EXPECT_THROW(SweepFetch(uint64_t{1} << 40, 8, 0), std::logic_error);
  EXPECT_THROW(SweepFetch(0, 1u << 22, 0), std::logic_error);
  EXPECT_THROW(SweepFetch(0, 8, 4), std::logic_error);
}

}  // namespace
}  // namespace rtusim
