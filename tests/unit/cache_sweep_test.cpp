// CacheSweep (one pass, every configuration) against one SetAssocCache per configuration over
// the same fetch stream: accesses and misses per stream tag must be equal for every policy,
// line size, set count and associativity, "full" (one set) included, with fetches straddling
// lines.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <stdexcept>

#include "cache/set_assoc_cache.h"
#include "sweep/cache_sweep.h"
#include "sweep/sweep_pipeline.h"
#include "sanitized.h"

namespace rtusim {
namespace {

// A stream with locality: mostly near the last address, sometimes a jump, sometimes a revisit.
// With `long_fetches`, one fetch in ten spans up to 3000 bytes and one in fifty ends at the
// image's last byte.
std::vector<SweepFetch> make_stream(uint64_t image_bytes, size_t n, uint32_t seed,
                                    bool long_fetches = false) {
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
    uint32_t bytes = (i % 17 == 0) ? 0 : 4 + static_cast<uint32_t>(rng() % 37);
    if (long_fetches && rng() % 10 == 0) bytes = 1 + static_cast<uint32_t>(rng() % 3000);
    const uint64_t at = long_fetches && rng() % 50 == 0 ? image_bytes - bytes
                                                        : std::min(addr, image_bytes - bytes);
    out.push_back({at, bytes, static_cast<uint32_t>(rng() % 3)});
  }
  return out;
}

// `configs` over `stream` in one pass, several ways (set counts in one part and in three;
// pipelines of 1, 2 and 3 threads holding 1 to 4 chunks of uneven sizes),
// against one SetAssocCache per configuration: accesses and misses per tag.
void expect_sweeps_equal_one_cache_each(const std::vector<CacheParams>& configs,
                                        uint64_t image_bytes,
                                        const std::vector<SweepFetch>& stream) {
  CacheSweep split(configs, image_bytes, 3);  // set counts split in three parts per line
  CacheSweep whole(configs, image_bytes);  // one part per line: every set count in one walk
  // Fed by pipelines: tasks run ahead of each other; without workers the pushing thread feeds.
  CacheSweep piped(configs, image_bytes, 2), pushed(configs, image_bytes, 2),
      tight(configs, image_bytes, 3);
  {
    SweepPipeline pipeline({&piped}, 3, 4), alone({&pushed}, 1, 4), one_held({&tight}, 2, 1);
    SweepPipeline::Lists chunk(1), chunk_alone(1), chunk_tight(1);
    std::mt19937 rng(5);
    for (size_t at = 0; at < stream.size();) {
      const size_t k = std::min<size_t>(rng() % 1500, stream.size() - at);  // empty ones too
      const auto part = std::span(stream).subspan(at, k);
      split.feed(part);
      whole.feed(part);
      for (const SweepFetch& f : part) {
        piped.record(chunk[0], f.addr(), f.bytes(), f.tag());
        pushed.record(chunk_alone[0], f.addr(), f.bytes(), f.tag());
        tight.record(chunk_tight[0], f.addr(), f.bytes(), f.tag());
      }
      pipeline.push(chunk);
      alone.push(chunk_alone);
      one_held.push(chunk_tight);
      at += k;
    }
    pipeline.finish();
    alone.finish();
    one_held.finish();
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
    for (const CacheSweep* s : {&split, &whole, &piped, &pushed, &tight}) {
      EXPECT_EQ(s->accesses(i), acc);
      EXPECT_EQ(s->misses(i), miss);
    }
    EXPECT_GT(miss[0] + miss[1] + miss[2], 0u);
  }
}

// Every configuration of `policies` x `lines` x `sizes` x `assocs` (0: full) that fits.
std::vector<CacheParams> configs_of(const std::vector<const char*>& policies,
                                    const std::vector<uint32_t>& lines,
                                    const std::vector<uint64_t>& sizes,
                                    const std::vector<uint32_t>& assocs) {
  std::vector<CacheParams> configs;
  for (const char* policy : policies)
    for (const uint32_t line : lines)
      for (const uint64_t size : sizes)
        for (const uint32_t assoc : assocs) {
          CacheParams c;
          c.policy = policy;
          c.line_bytes = line;
          c.size_bytes = size;
          c.assoc = assoc ? assoc : static_cast<uint32_t>(size / line);
          c.seed = 7;
          if (size >= uint64_t{line} * c.assoc) configs.push_back(c);
        }
  return configs;
}

// Lines 16, 32, 64 B x sizes 256 B .. 4 KB.
void expect_equal_to_one_cache_each(const std::vector<const char*>& policies,
                                    const std::vector<uint32_t>& assocs) {
  const uint64_t image_bytes = 1 << 16;
  expect_sweeps_equal_one_cache_each(configs_of(policies, {16, 32, 64}, {256, 1024, 4096}, assocs),
                                     image_bytes,
                                     make_stream(image_bytes, testing::sanitized_share(200000), 1));
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

TEST(CacheSweep, EncodedLinesAtEveryLineSize) {
  // The line stream is encoded at the finest LRU line size (8 B) and read at sizes up to 7 bits
  // coarser, with fetches spanning many lines and ending at the image's last byte; LRU beside
  // the other policies, and the other policies alone (no line stream).
  const uint64_t image_bytes = 1 << 18;
  const auto stream = make_stream(image_bytes, testing::sanitized_share(60000), 2,
                                  /*long_fetches=*/true);
  const std::vector<uint64_t> sizes = {1024, 4096};
  const std::vector<uint32_t> assocs = {1, 2, 16, 0};
  expect_sweeps_equal_one_cache_each(
      configs_of({"lru"}, {8, 16, 64, 256, 1024}, sizes, assocs), image_bytes, stream);
  expect_sweeps_equal_one_cache_each(
      configs_of({"lru", "fifo", "tree-plru"}, {32, 128}, sizes, assocs), image_bytes, stream);
  expect_sweeps_equal_one_cache_each(configs_of({"fifo", "random"}, {16, 64}, sizes, assocs),
                                     image_bytes, stream);
}

TEST(CacheSweep, LineNumberLimitOnlyWithLru) {
  // Encoded lines hold 29 bits of line number: an LRU sweep refuses a larger image; a sweep of
  // other policies encodes nothing and takes any.
  CacheParams lru;
  lru.line_bytes = 16;
  lru.size_bytes = 1024;
  lru.assoc = 4;
  const uint64_t largest = ((uint64_t{1} << 29) - 1) * 16 - 1;
  EXPECT_NO_THROW(CacheSweep({lru}, largest));
  EXPECT_THROW(CacheSweep({lru}, largest + 1), std::logic_error);
  CacheParams fifo = lru;
  fifo.policy = "fifo";
  EXPECT_NO_THROW(CacheSweep({fifo}, uint64_t{1} << 40));
  // A fetch beyond the image is refused, not wrapped into the words.
  CacheSweep small({lru}, 4096);
  SweepChunk chunk;
  EXPECT_NO_THROW(small.record(chunk, 4088, 8, 0));
  EXPECT_THROW(small.record(chunk, 1 << 20, 8, 0), std::logic_error);
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
