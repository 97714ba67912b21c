// Node L1: hit, miss, merged miss and MSHR-full stalls with exact cycle counts, against a
// memory of fixed latency answering at once or later (the AT path).
#include <gtest/gtest.h>

#include "mem/l1_cache.h"
#include "sc_fixture.h"
#include "tlm_test_modules.h"
#include "util/error.h"
#include "util/stats.h"

namespace rtusim {
namespace {

using testing::FixedLatencyMemory;
using testing::Requester;

constexpr uint64_t kCycle = 1000;            // 1 GHz
constexpr uint64_t kMemLatency = 50 * kCycle;  // the memory's fixed latency
constexpr uint64_t X = 0x1000, Y = 0x2000, W = 0x3000;  // three lines, one set of a 4-way cache

L1Params l1_params(uint32_t mshrs) {
  L1Params p;
  p.cache.size_bytes = 8192;
  p.cache.assoc = 4;
  p.cache.line_bytes = 64;
  p.hit_cycles = 2;
  p.mshrs = mshrs;
  p.clock_period_ps = kCycle;
  return p;
}

struct Bench {
  Requester req;
  L1Cache l1;
  FixedLatencyMemory mem;
  Bench(std::vector<Requester::Req> r, uint32_t mshrs, bool deferred)
      : req("req", std::move(r)), l1("l1", l1_params(mshrs)),
        mem("mem", kMemLatency, deferred) {
    req.socket.bind(l1.target_socket);
    l1.initiator_socket.bind(mem.socket);
  }
};

class L1CacheTest : public testing::SystemCTest, public ::testing::WithParamInterface<bool> {};

TEST_P(L1CacheTest, MissThenHit) {
  Bench b({{0, X + 8}, {60 * kCycle, X + 16}}, 8, GetParam());
  sc_core::sc_start();
  // Miss: tag check 2 cycles, memory 50: the line is there at cycle 52.
  EXPECT_EQ(b.req.done_ps[0], 52 * kCycle);
  EXPECT_EQ(b.req.done_ps[1], 62 * kCycle);  // hit: 2 cycles
  ASSERT_EQ(b.mem.arrivals.size(), 1u);
  EXPECT_EQ(b.mem.arrivals[0].addr, X);  // the whole line
  EXPECT_EQ(b.mem.arrivals[0].bytes, 64u);
  EXPECT_EQ(b.mem.arrivals[0].at_ps, 2 * kCycle);
  EXPECT_EQ(b.l1.hits(), 1u);
  EXPECT_EQ(b.l1.primary_misses(), 1u);
  EXPECT_EQ(b.l1.merged_misses(), 0u);
  EXPECT_DOUBLE_EQ(b.l1.mean_miss_latency_cycles(), 52.0);
}

TEST_P(L1CacheTest, SecondaryMissMergesOnTheMshr) {
  Bench b({{0, X}, {5 * kCycle, X + 32}, {7 * kCycle, Y}}, 8, GetParam());
  sc_core::sc_start();
  EXPECT_EQ(b.req.done_ps[0], 52 * kCycle);
  EXPECT_EQ(b.req.done_ps[1], 52 * kCycle);  // with the primary's fill
  EXPECT_EQ(b.req.done_ps[2], 59 * kCycle);  // non-blocking: its own miss overlaps
  EXPECT_EQ(b.mem.arrivals.size(), 2u);
  EXPECT_EQ(b.l1.primary_misses(), 2u);
  EXPECT_EQ(b.l1.merged_misses(), 1u);
  EXPECT_EQ(b.l1.hits(), 0u);
  EXPECT_EQ(b.l1.bytes_from_dram(), 128u);
  Stats s;
  b.l1.write_stats(s, "l1");
  EXPECT_EQ(s.at("l1.misses").get<uint64_t>(), 3u);
  EXPECT_EQ(s.at("l1.accesses").get<uint64_t>(), 3u);
}

TEST_P(L1CacheTest, FullMshrsStallMissesNotHits) {
  // One MSHR. X misses at 0 (fill 52). Y misses at 1: waits for X's MSHR until 52, goes to
  // memory at 54, fills at 104. W misses at 2: waits behind Y until 104, fills at 156. A hit
  // on line 0x0 (filled first, at 0..?) goes on meanwhile.
  Bench b({{0, 0x0}, {60 * kCycle, X}, {61 * kCycle, Y}, {62 * kCycle, W}, {63 * kCycle, 0x8}},
          1, GetParam());
  sc_core::sc_start();
  EXPECT_EQ(b.req.done_ps[0], 52 * kCycle);
  EXPECT_EQ(b.req.done_ps[1], 112 * kCycle);
  EXPECT_EQ(b.req.done_ps[2], 164 * kCycle);   // stalled 51 cycles (61 -> 112)
  EXPECT_EQ(b.req.done_ps[3], 216 * kCycle);   // stalled 102 cycles (62 -> 164)
  EXPECT_EQ(b.req.done_ps[4], 65 * kCycle);    // a hit while misses stall
  EXPECT_EQ(b.l1.mshr_stall_cycles(), 51u + 102u);
  EXPECT_EQ(b.l1.primary_misses(), 4u);
  EXPECT_EQ(b.l1.hits(), 1u);
  ASSERT_EQ(b.mem.arrivals.size(), 4u);
  EXPECT_EQ(b.mem.arrivals[2].at_ps, 114 * kCycle);
  EXPECT_EQ(b.mem.arrivals[3].at_ps, 166 * kCycle);
  // Latency from request to fill, stalls included: 52, 52, 103, 154.
  EXPECT_DOUBLE_EQ(b.l1.mean_miss_latency_cycles(), (52.0 + 52 + 103 + 154) / 4);
}

INSTANTIATE_TEST_SUITE_P(MemoryAnswers, L1CacheTest, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& i) { return i.param ? "Later" : "AtOnce"; });

TEST(L1ParamsTest, ValidationNamesTheKey) {
  L1Params p = l1_params(0);
  try {
    validate(p, "l1");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("l1.mshrs"), std::string::npos);
  }
}

}  // namespace
}  // namespace rtusim
