// Node L1: hit, miss, merged miss, one lookup per cycle, MSHR-full blocking and a pending line's
// eviction, with exact cycle counts, against a memory of fixed latency answering at once or
// later (the AT path), and behind the FR-FCFS DRAM when it decides several reads at once.
#include <gtest/gtest.h>

#include "mem/dram/dram.h"
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
  Bench(std::vector<Requester::Req> r, uint32_t mshrs, bool deferred,
        uint64_t mem_latency_ps = kMemLatency)
      : req("req", std::move(r)), l1("l1", l1_params(mshrs)),
        mem("mem", mem_latency_ps, deferred) {
    req.socket.bind(l1.target_socket);
    l1.initiator_socket.bind(mem.socket);
    if (deferred) l1.set_downstream_horizon(&mem);
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

TEST_P(L1CacheTest, FullMshrsBlockThePortInOrder) {
  // One MSHR. Line 0 misses at 0 (fill 52). X misses at 60 (fill 112). Y at 61 finds the MSHR
  // busy: the port blocks until X's fill, Y misses at 112 (memory at 114, fill 164). W, at 62,
  // waits for the port, looks up at 113, blocks until 164 (fill 216). The hit on line 0 at 63
  // waits behind them all: looks up at 165, answered at 167.
  Bench b({{0, 0x0}, {60 * kCycle, X}, {61 * kCycle, Y}, {62 * kCycle, W}, {63 * kCycle, 0x8}},
          1, GetParam());
  sc_core::sc_start();
  EXPECT_EQ(b.req.done_ps[0], 52 * kCycle);
  EXPECT_EQ(b.req.done_ps[1], 112 * kCycle);
  EXPECT_EQ(b.req.done_ps[2], 164 * kCycle);
  EXPECT_EQ(b.req.done_ps[3], 216 * kCycle);
  EXPECT_EQ(b.req.done_ps[4], 167 * kCycle);
  EXPECT_EQ(b.l1.mshr_stall_cycles(), (112u - 61u) + (164u - 113u));
  EXPECT_EQ(b.l1.primary_misses(), 4u);
  EXPECT_EQ(b.l1.hits(), 1u);
  ASSERT_EQ(b.mem.arrivals.size(), 4u);
  EXPECT_EQ(b.mem.arrivals[2].at_ps, 114 * kCycle);
  EXPECT_EQ(b.mem.arrivals[3].at_ps, 166 * kCycle);
  // Latency from request to fill, port wait and stall included: 52, 52, 103, 154.
  EXPECT_DOUBLE_EQ(b.l1.mean_miss_latency_cycles(), (52.0 + 52 + 103 + 154) / 4);
}

TEST_P(L1CacheTest, OneLookupPerCycle) {
  // Three misses presented in cycle 0 look up at 0, 1 and 2; a hit at 1 waits until 3.
  Bench b({{0, X}, {0, Y}, {0, W}, {1 * kCycle, 0x40}, {60 * kCycle, X}, {60 * kCycle, Y}}, 8,
          GetParam());
  sc_core::sc_start();
  EXPECT_EQ(b.req.done_ps[0], 52 * kCycle);
  EXPECT_EQ(b.req.done_ps[1], 53 * kCycle);
  EXPECT_EQ(b.req.done_ps[2], 54 * kCycle);
  EXPECT_EQ(b.req.done_ps[3], 55 * kCycle);  // a miss looked up at 3: memory at 5
  EXPECT_EQ(b.req.done_ps[4], 62 * kCycle);  // hits at 60 and 61
  EXPECT_EQ(b.req.done_ps[5], 63 * kCycle);
  ASSERT_EQ(b.mem.arrivals.size(), 4u);
  EXPECT_EQ(b.mem.arrivals[1].at_ps, 3 * kCycle);
  EXPECT_EQ(b.l1.primary_misses(), 4u);
  EXPECT_EQ(b.l1.hits(), 2u);
  EXPECT_EQ(b.l1.mshr_stall_cycles(), 0u);
  // The latency counts the port wait: 52, 53, 54, 54.
  EXPECT_DOUBLE_EQ(b.l1.mean_miss_latency_cycles(), (52.0 + 53 + 54 + 54) / 4);
}

TEST_P(L1CacheTest, SeventyMshrsBeyondOneBitMask) {
  // 70 MSHRs (two 64-wide masks), memory 100 cycles. Misses on 70 lines at cycles 0..69 take
  // MSHRs 0..69 and fill at 102..171. A 71st line at 70 finds them all busy: the port blocks
  // until the first fill (102), the read goes at 104, the fill is at 204. A request at 71 for
  // line 66 (MSHR 66, in the second mask) looks up at 103 and merges: answered at its fill, 168.
  std::vector<Requester::Req> r;
  for (uint64_t i = 0; i < 70; ++i) r.push_back({i * kCycle, i * 64});
  r.push_back({70 * kCycle, 70 * 64});
  r.push_back({71 * kCycle, 66 * 64 + 8});
  Bench b(std::move(r), 70, GetParam(), 100 * kCycle);
  sc_core::sc_start();
  for (uint64_t i = 0; i < 70; ++i) EXPECT_EQ(b.req.done_ps[i], (i + 102) * kCycle) << i;
  EXPECT_EQ(b.req.done_ps[70], 204 * kCycle);
  EXPECT_EQ(b.req.done_ps[71], 168 * kCycle);
  EXPECT_EQ(b.l1.primary_misses(), 71u);
  EXPECT_EQ(b.l1.merged_misses(), 1u);
  EXPECT_EQ(b.l1.mshr_stall_cycles(), 102u - 70u);
  ASSERT_EQ(b.mem.arrivals.size(), 71u);
  EXPECT_EQ(b.mem.arrivals[70].at_ps, 104 * kCycle);
}

TEST_P(L1CacheTest, ABacklogOfThousandsOneLookupPerCycle) {
  // 3000 requests at cycle 0 on four lines wait in the port's backlog and look up one per cycle:
  // request i at cycle i. Line k = i % 4 misses at cycle k and fills at k + 52; a lookup before
  // the fill merges (answered at the fill), one at or after it hits (answered 2 cycles later).
  std::vector<Requester::Req> r;
  for (uint64_t i = 0; i < 3000; ++i) r.push_back({0, (i % 4) * 64 + 8});
  Bench b(std::move(r), 8, GetParam());
  sc_core::sc_start();
  uint64_t hits = 0, merged = 0;
  for (uint64_t i = 0; i < 3000; ++i) {
    const uint64_t fill = i % 4 + 52;
    const bool hit = i >= 4 && i >= fill;
    hits += hit;
    merged += i >= 4 && !hit;
    EXPECT_EQ(b.req.done_ps[i], (hit ? i + 2 : fill) * kCycle) << i;
  }
  EXPECT_EQ(b.l1.primary_misses(), 4u);
  EXPECT_EQ(b.l1.merged_misses(), merged);
  EXPECT_EQ(b.l1.hits(), hits);
}

TEST_P(L1CacheTest, MergeInTheLastCycleBeforeTheFillThenHit) {
  // X fills at 52: a lookup at 51 merges (answered at 52), one at 52 hits (answered at 54).
  Bench b({{0, X}, {51 * kCycle, X + 8}, {52 * kCycle, X + 16}}, 8, GetParam());
  sc_core::sc_start();
  EXPECT_EQ(b.req.done_ps[1], 52 * kCycle);
  EXPECT_EQ(b.req.done_ps[2], 54 * kCycle);
  EXPECT_EQ(b.l1.merged_misses(), 1u);
  EXPECT_EQ(b.l1.hits(), 1u);
}

TEST_P(L1CacheTest, APendingLineEvictedIsReinstalledByItsMerge) {
  // Five lines of one 4-way set miss at 0..4 (allocate on miss): U evicts X while X's read is
  // pending. X + 8 at 5 still merges on X's MSHR (answered at X's fill), and its tag access
  // installs X again, evicting Y (the least recent). Y at 60 misses again.
  constexpr uint64_t V = 0x4000, U = 0x5000;
  Bench b({{0, X}, {1 * kCycle, Y}, {2 * kCycle, W}, {3 * kCycle, V}, {4 * kCycle, U},
           {5 * kCycle, X + 8}, {60 * kCycle, Y}, {61 * kCycle, X}},
          8, GetParam());
  sc_core::sc_start();
  EXPECT_EQ(b.req.done_ps[5], 52 * kCycle);
  EXPECT_EQ(b.req.done_ps[6], 112 * kCycle);
  EXPECT_EQ(b.req.done_ps[7], 63 * kCycle);
  EXPECT_EQ(b.l1.primary_misses(), 6u);
  EXPECT_EQ(b.l1.merged_misses(), 1u);
  EXPECT_EQ(b.l1.hits(), 1u);
}

INSTANTIATE_TEST_SUITE_P(MemoryAnswers, L1CacheTest, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& i) { return i.param ? "Later" : "AtOnce"; });

class L1BehindDramTest : public testing::SystemCTest {};

TEST_F(L1BehindDramTest, FillsDecidedTogetherAllPrecedeLaterLookups) {
  // The FR-FCFS DRAM (one channel, 4 banks, 1 KB rows: bank = (addr / 1024) % 4, row =
  // addr / 4096) decides two of the L1's reads at one time and answers them one by one. The
  // first answer's fill lets the L1 decide the lookup queued behind it; the second fill comes
  // before that lookup, so it must be known first (was: the DRAM's horizon had moved past the
  // second completion while it was not answered yet, the lookup was decided on the first fill
  // and the second fill threw logic_error).
  DramParams dp;
  dp.banks = 4;
  dp.row_bytes = 1024;
  constexpr uint64_t kBank0Row0 = 0x0000, kBank1Row0 = 0x0400;  // opened by another initiator
  constexpr uint64_t A = 0x1000, B = 0x1400;                       // row 1 of banks 0 and 1
  constexpr uint64_t kLateLookup = 100;  // a hit on A after both fills
  // The L1 runs ahead of the kernel (as the unit does): the late lookup is queued from the
  // start, behind the DRAM's horizon.
  Requester unit("unit", {{0, A}, {1 * kCycle, B}, {kLateLookup * kCycle, A + 8}});
  unit.run_ahead_ps = kLateLookup * kCycle;
  Requester other("other", {{0, kBank0Row0, 64}, {0, kBank1Row0, 64}});
  L1Cache l1("l1", l1_params(2));
  Dram dram("dram", dp);
  unit.socket.bind(l1.target_socket);
  l1.initiator_socket.bind(dram.target_socket);
  other.socket.bind(dram.target_socket);
  l1.set_downstream_horizon(&dram);
  EXPECT_NO_THROW(sc_core::sc_start());

  // Rows 0 open at tRCD; banks 0 and 1 are both ready at tRCD + tBurst, where A and B (sent
  // at cycles 2 and 3) are row conflicts decided together, A first (older); B's data follows
  // A's on the bus.
  const uint64_t rcd = dp.tRCD_ps(), rp = dp.tRP_ps(), cl = dp.tCL_ps(), burst = dp.burst_ps();
  const uint64_t a_done_ps = (rcd + burst) + rp + rcd + cl + burst;
  const uint64_t b_done_ps = a_done_ps + burst;
  auto fill_ps = [](uint64_t done_ps) { return (done_ps + kCycle - 1) / kCycle * kCycle; };
  ASSERT_LT(fill_ps(b_done_ps), kLateLookup * kCycle);  // the case this test is about
  EXPECT_EQ(unit.done_ps[0], fill_ps(a_done_ps));
  EXPECT_EQ(unit.done_ps[1], fill_ps(b_done_ps));
  EXPECT_EQ(unit.done_ps[2], (kLateLookup + 2) * kCycle);  // a hit at its own time
  EXPECT_EQ(l1.primary_misses(), 2u);
  EXPECT_EQ(l1.hits(), 1u);
  EXPECT_EQ(dram.horizon_ps(), MemoryHorizon::kNever);
}

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
