// The RTL L1's cycle-level behaviour against the node L1 timing spec v2 (rtl_model/README.md),
// with exact edges: hit and primary-miss latency, merges (one in the fill's last cycle), a full
// set of MSHRs blocking a primary until the earliest fill, one lookup and one fill per cycle,
// the eviction of a pending line and the merge that installs it again (every build, so both
// policies), response back-pressure; and random traffic on every build checked against a
// shadow of the spec built on SetAssocCache.
//
// The bench plays the adapter's part: it keeps the requests waiting on each MSHR (from
// o_req_mshr) and answers them at the edge that ends their fill's cycle (o_fill_mshr), hits when
// o_resp_valid is taken. Edges are counted from the bench's start; a request accepted at edge a
// was looked up in cycle a-1, so the spec's "answer at c + 2" is edge a + 1.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "cache/set_assoc_cache.h"
#include "rtl/rtl_l1_registry.h"
#include "rtl_l1_harness.h"

namespace rtusim::rtltest {
namespace {

constexpr uint32_t kMshrs = 8;

struct Response {
  uint64_t edge;
  uint32_t id;
  Outcome outcome;
};

struct Lookup {
  uint64_t edge;  // accepted at
  Outcome outcome;
  uint32_t mshr;
};

std::string test_name(const testing::TestParamInfo<RtlL1Build>& i) {
  std::string s(i.param.model);
  std::replace(s.begin(), s.end(), '-', '_');
  return s;
}

// Cycle-by-cycle driver with a memory of configurable latency: a line read taken at edge s is
// filled in the cycle ending at edge s + latency, or the first later edge no other fill holds
// (one fill per cycle).
class Bench {
 public:
  explicit Bench(const CacheParams& p = CacheParams{}, uint32_t mem_latency = 10)
      : m_(make_cpp_model(std::string(rtl_l1_build(p).model))), latency_(mem_latency) {}

  Inputs in;                        // request-side inputs, driven every cycle
  std::vector<Response> responses;  // in the order they were answered
  std::map<uint32_t, Lookup> lookups;  // by id
  std::vector<uint64_t> mem_requests;  // line addresses, in the order taken
  uint64_t edge = 0;                   // edges so far
  std::function<uint32_t()> latency_fn;  // per line read; default the fixed latency
  std::function<void(uint64_t edge, uint32_t mshr)> on_fill;  // at the edge that ends a fill
  Outputs last;   // outputs of the last cycle driven
  Inputs last_in;

  // One cycle: drive, sample, rising edge. Returns whether the offered request was accepted.
  bool tick() {
    Inputs drive = in;
    drive.mem_resp_valid = false;
    if (!fills_.empty() && fills_.begin()->first == edge + 1) {
      drive.mem_resp_valid = true;
      drive.mem_resp_addr = fills_.begin()->second;
    }
    m_->drive(drive);
    last = m_->outputs();
    last_in = drive;
    ++edge;
    const bool accepted = drive.req_valid && last.req_ready;
    if (accepted) {
      const Outcome o = last.req_hit      ? Outcome::kHit
                        : last.req_merged ? Outcome::kMergedMiss
                                          : Outcome::kPrimaryMiss;
      lookups[drive.req_id] = {edge, o, last.req_mshr};
      if (o != Outcome::kHit) waiters_[last.req_mshr].push_back(drive.req_id);
    }
    if (drive.mem_resp_valid) {
      EXPECT_TRUE(last.fill_valid) << "a fill matched no waiting MSHR, edge " << edge;
      for (const uint32_t id : waiters_[last.fill_mshr])
        responses.push_back({edge, id, lookups[id].outcome});
      waiters_[last.fill_mshr].clear();
      if (on_fill) on_fill(edge, last.fill_mshr);
      fills_.erase(fills_.begin());
    }
    if (last.resp_valid && drive.resp_ready)
      responses.push_back({edge, last.resp_id, Outcome::kHit});
    if (last.mem_req_valid && drive.mem_req_ready) {
      mem_requests.push_back(last.mem_req_addr);
      uint64_t due = edge + (latency_fn ? latency_fn() : latency_);
      while (fills_.count(due)) ++due;
      fills_.emplace(due, last.mem_req_addr);
    }
    m_->posedge();
    return accepted;
  }

  // Offers a request until it is accepted; returns the accepting edge.
  uint64_t request(uint64_t addr, uint32_t id) {
    in.req_valid = true;
    in.req_addr = addr;
    in.req_id = id;
    for (int i = 0; i < 10000; ++i)
      if (tick()) {
        in.req_valid = false;
        return edge;
      }
    ADD_FAILURE() << "request 0x" << std::hex << addr << " never accepted";
    in.req_valid = false;
    return edge;
  }

  // Runs until the response for `id` has been answered; returns it.
  Response await(uint32_t id) {
    for (int i = 0; i < 10000; ++i) {
      for (const Response& r : responses)
        if (r.id == id) return r;
      tick();
    }
    ADD_FAILURE() << "no response for id " << id;
    return {};
  }

  void idle(int cycles) {
    for (int i = 0; i < cycles; ++i) tick();
  }
  // Runs until the next cycle driven is the one that edge `e` ends.
  void idle_until(uint64_t e) {
    while (edge + 1 < e) tick();
  }

  // The edge whose cycle fills `line` (its fill is scheduled); 0 if none.
  uint64_t fill_edge(uint64_t line_addr) const {
    for (const auto& [e, a] : fills_)
      if (a == line_addr) return e;
    return 0;
  }

 private:
  std::unique_ptr<RtlL1Model> m_;
  uint32_t latency_;
  std::map<uint64_t, uint64_t> fills_;  // due edge -> line address
  std::array<std::vector<uint32_t>, kMshrs> waiters_;
};

TEST(RtlL1Timing, HitIsAnsweredTwoCyclesAfterItsLookup) {
  Bench b;
  b.request(0x4000, 1);
  b.await(1);
  const uint64_t a = b.request(0x4020, 2);
  EXPECT_EQ(b.lookups[2].outcome, Outcome::kHit);
  const Response r = b.await(2);
  EXPECT_EQ(r.outcome, Outcome::kHit);
  EXPECT_EQ(r.edge, a + 1) << "looked up in cycle a-1, answered at (a-1) + 2";
  // Back-to-back hits: one looked up and one answered per cycle.
  const uint64_t first = b.edge + 1;
  for (uint32_t i = 0; i < 16; ++i) EXPECT_EQ(b.request(0x4000 + 4 * i, 10 + i), first + i);
  for (uint32_t i = 0; i < 16; ++i) EXPECT_EQ(b.await(10 + i).edge, first + i + 1);
  EXPECT_EQ(b.mem_requests.size(), 1u);
}

TEST(RtlL1Timing, PrimaryMissReadsTheLineTwoCyclesAfterItsLookupAndIsAnsweredAtItsFill) {
  for (uint32_t latency : {1u, 2u, 10u, 100u}) {
    SCOPED_TRACE(latency);
    Bench b(CacheParams{}, latency);
    uint64_t fill_edge = 0;
    b.on_fill = [&](uint64_t e, uint32_t) { fill_edge = e; };
    const uint64_t a = b.request(0x12345, 7);
    EXPECT_EQ(b.lookups[7].outcome, Outcome::kPrimaryMiss);
    EXPECT_EQ(b.lookups[7].mshr, 0u) << "the lowest free MSHR";
    b.tick();  // cycle a: the line read is on the outputs
    EXPECT_TRUE(b.last.mem_req_valid);
    EXPECT_EQ(b.last.mshrs_busy, 1u);
    ASSERT_EQ(b.mem_requests.size(), 1u);
    EXPECT_EQ(b.edge, a + 1) << "read taken at (a-1) + 2";
    EXPECT_EQ(b.mem_requests[0], 0x12340u) << "the line's first byte";
    const Response r = b.await(7);
    EXPECT_EQ(r.outcome, Outcome::kPrimaryMiss);
    EXPECT_EQ(fill_edge, a + 1 + latency);
    EXPECT_EQ(r.edge, fill_edge);
    b.tick();
    EXPECT_EQ(b.last.mshrs_busy, 0u) << "free from the fill's edge";
  }
}

TEST(RtlL1Timing, MergesAreAnsweredAtTheFillIncludingOneInItsLastCycle) {
  Bench b(CacheParams{}, 20);
  const uint64_t a = b.request(0x8000, 1);
  EXPECT_EQ(b.request(0x8008, 2), a + 1);
  EXPECT_EQ(b.request(0x8030, 3), a + 2);
  EXPECT_EQ(b.lookups[2].outcome, Outcome::kMergedMiss);
  EXPECT_EQ(b.lookups[3].outcome, Outcome::kMergedMiss);
  EXPECT_EQ(b.lookups[3].mshr, b.lookups[1].mshr);
  const Response r1 = b.await(1), r2 = b.await(2), r3 = b.await(3);
  EXPECT_EQ(b.mem_requests.size(), 1u);
  EXPECT_EQ(r1.edge, a + 1 + 20);
  EXPECT_EQ(r2.edge, r1.edge);
  EXPECT_EQ(r3.edge, r1.edge);

  // A lookup in the fill's own cycle still merges, and is answered at that fill; one in the next
  // cycle hits.
  b.request(0x9000, 4);
  b.tick();  // the read is taken: the fill is scheduled
  const uint64_t fill = b.fill_edge(0x9000);
  ASSERT_NE(fill, 0u);
  b.idle_until(fill);
  EXPECT_EQ(b.request(0x9010, 5), fill);
  EXPECT_TRUE(b.last_in.mem_resp_valid) << "looked up in the fill's cycle";
  EXPECT_EQ(b.lookups[5].outcome, Outcome::kMergedMiss);
  EXPECT_EQ(b.await(5).edge, fill);
  EXPECT_EQ(b.await(4).edge, fill);
  EXPECT_EQ(b.request(0x9020, 6), fill + 1);
  EXPECT_EQ(b.lookups[6].outcome, Outcome::kHit);
  EXPECT_EQ(b.await(6).edge, fill + 2);
  EXPECT_EQ(b.mem_requests.size(), 2u);
}

TEST(RtlL1Timing, AFullSetOfMshrsBlocksAPrimaryUntilTheEarliestFill) {
  Bench b(CacheParams{}, 5);
  b.request(0x100000, 100);  // a line to hit later
  b.await(100);
  // Eight primaries (lines in different sets); the fourth has the shortest memory latency, so
  // MSHR 3 frees first.
  uint32_t n = 0;
  b.latency_fn = [&] { return n++ == 3 ? 20u : 50u; };
  const uint64_t a0 = b.request(0x200040, 0);
  for (uint32_t i = 1; i < kMshrs; ++i)
    EXPECT_EQ(b.request(0x200040 + 0x40 * i, i), a0 + i) << "back to back while MSHRs are free";
  for (uint32_t i = 0; i < kMshrs; ++i) EXPECT_EQ(b.lookups[i].mshr, i);
  b.tick();  // the last read is taken
  EXPECT_EQ(b.last.mshrs_busy, kMshrs);
  const uint64_t earliest = b.fill_edge(0x200100);
  ASSERT_NE(earliest, 0u);
  // Under full MSHRs a hit and a merge still go through.
  const uint64_t ah = b.request(0x100008, 51);
  EXPECT_EQ(b.lookups[51].outcome, Outcome::kHit);
  EXPECT_EQ(b.await(51).edge, ah + 1);
  b.request(0x200050, 52);
  EXPECT_EQ(b.lookups[52].outcome, Outcome::kMergedMiss);
  EXPECT_EQ(b.lookups[52].mshr, 0u);
  // A new primary is refused every cycle up to and including the fill's, then takes MSHR 3.
  ASSERT_LT(b.edge + 1, earliest);
  b.in.req_valid = true;
  b.in.req_addr = 0x300000;
  b.in.req_id = 50;
  const uint64_t offered = b.edge + 1;
  while (!b.tick()) {
    EXPECT_FALSE(b.last.req_ready) << "edge " << b.edge;
    ASSERT_LE(b.edge, earliest) << "not accepted in the cycle after the fill";
  }
  b.in.req_valid = false;
  EXPECT_EQ(b.edge, earliest + 1);
  EXPECT_EQ(b.lookups[50].outcome, Outcome::kPrimaryMiss);
  EXPECT_EQ(b.lookups[50].mshr, 3u);
  EXPECT_EQ(earliest - offered + 1, b.edge - offered) << "refused cycles = T_free - c";
  const Response r3 = b.await(3);
  EXPECT_EQ(r3.edge, earliest);
  b.tick();
  EXPECT_EQ(b.mem_requests.back(), 0x300000u);
  EXPECT_EQ(b.await(52).outcome, Outcome::kMergedMiss);
  EXPECT_EQ(b.await(50).outcome, Outcome::kPrimaryMiss);
  EXPECT_EQ(b.mem_requests.size(), 1u + kMshrs + 1u);
}

TEST(RtlL1Timing, OneLookupAndOneFillPerCycle) {
  Bench b(CacheParams{}, 30);
  b.request(0x40000, 90);  // a line to hit (set 0; the misses below are in other sets)
  b.await(90);
  // Mixed outcomes on consecutive edges: hit, primary, merge, primary, hit, merge.
  const uint64_t a = b.request(0x40004, 0);
  const uint64_t addrs[] = {0x50040, 0x50044, 0x51080, 0x40008, 0x51088};
  for (uint32_t i = 0; i < 5; ++i) EXPECT_EQ(b.request(addrs[i], 1 + i), a + 1 + i);
  const Outcome expected[] = {Outcome::kHit, Outcome::kPrimaryMiss, Outcome::kMergedMiss,
                              Outcome::kPrimaryMiss, Outcome::kHit, Outcome::kMergedMiss};
  for (uint32_t i = 0; i < 6; ++i) EXPECT_EQ(b.lookups[i].outcome, expected[i]) << i;
  // Four more primaries on consecutive edges: their fills come on consecutive edges, each frees
  // one MSHR, and hits are looked up in every one of those cycles.
  for (uint32_t i = 0; i < 4; ++i) b.request(0x600c0 + 0x40 * i, 10 + i);
  std::vector<uint64_t> fill_edges;
  b.on_fill = [&](uint64_t e, uint32_t) { fill_edges.push_back(e); };
  b.in.req_valid = true;
  b.in.req_addr = 0x40000;
  uint32_t id = 20;
  while (fill_edges.size() < 6) {
    b.in.req_id = id;
    EXPECT_TRUE(b.tick()) << "a hit is refused at edge " << b.edge;
    ++id;
  }
  b.in.req_valid = false;
  ASSERT_EQ(fill_edges.size(), 6u);
  EXPECT_EQ(fill_edges[1], fill_edges[0] + 2);  // the two first primaries, two lookups apart
  for (size_t i = 3; i < 6; ++i) EXPECT_EQ(fill_edges[i], fill_edges[i - 1] + 1) << i;
  for (uint32_t i = 0; i < 4; ++i) EXPECT_EQ(b.await(10 + i).edge, fill_edges[2 + i]);
  EXPECT_EQ(b.await(1).edge, fill_edges[0]);
  EXPECT_EQ(b.await(2).edge, fill_edges[0]);
  EXPECT_EQ(b.await(3).edge, fill_edges[1]);
  EXPECT_EQ(b.await(5).edge, fill_edges[1]);
}

TEST(RtlL1Timing, ResponseBackPressureHoldsTheHitAndRefusesOnlyHits) {
  Bench b(CacheParams{}, 40);
  b.request(0x7000, 1);
  b.await(1);
  b.in.resp_ready = false;
  const uint64_t a = b.request(0x7000, 2);
  b.tick();
  EXPECT_TRUE(b.last.resp_valid);
  EXPECT_EQ(b.last.resp_id, 2u);
  // Held: another hit is refused; a primary and a merge are not.
  b.in.req_valid = true;
  b.in.req_addr = 0x7008;
  b.in.req_id = 3;
  for (int i = 0; i < 4; ++i) EXPECT_FALSE(b.tick());
  EXPECT_TRUE(b.last.resp_valid);
  EXPECT_EQ(b.last.resp_id, 2u);
  b.in.req_valid = false;
  b.request(0xa000, 4);
  b.request(0xa008, 5);
  EXPECT_EQ(b.lookups[4].outcome, Outcome::kPrimaryMiss);
  EXPECT_EQ(b.lookups[5].outcome, Outcome::kMergedMiss);
  // Released: the held response is taken, and the hit goes in at the same edge.
  b.in.resp_ready = true;
  const uint64_t a3 = b.request(0x7008, 3);
  ASSERT_EQ(b.responses.size(), 2u);
  EXPECT_EQ(b.responses[1].id, 2u);
  EXPECT_EQ(b.responses[1].edge, a3);
  EXPECT_GT(a3, a + 6);
  EXPECT_EQ(b.await(3).edge, a3 + 1);
  EXPECT_EQ(b.await(5).edge, b.await(4).edge);
}

class RtlL1Builds : public testing::TestWithParam<RtlL1Build> {};

// Spec item 3: a merge into a pending line that the tags evicted meanwhile installs it again.
TEST_P(RtlL1Builds, AMergeInstallsItsPendingLineAgainAfterAnEviction) {
  const CacheParams p = GetParam().cache();
  Bench b(p, 5);
  SetAssocCache shadow(p);
  uint32_t latency = 5;
  b.latency_fn = [&] { return latency; };
  const uint64_t set_stride = p.size_bytes / p.assoc;  // same set, next tag
  uint32_t id = 0;
  auto access = [&](uint64_t addr) {
    const uint32_t i = id++;
    const bool shadow_hit = shadow.access(addr);
    b.request(addr, i);
    const Outcome o = b.lookups[i].outcome;
    if (o != Outcome::kMergedMiss) {
      EXPECT_EQ(o == Outcome::kHit, shadow_hit) << "access " << i;
    }
    return i;
  };
  // Fill the set, then miss on L with a long memory latency.
  for (uint32_t w = 0; w < p.assoc; ++w) b.await(access(set_stride * (w + 1)));
  const uint64_t line = 0;
  latency = 400;
  const uint32_t primary = access(line);
  EXPECT_EQ(b.lookups[primary].outcome, Outcome::kPrimaryMiss);
  b.tick();  // the line read is taken with the long latency
  latency = 5;
  // Other lines of the set until the tags have evicted L (the shadow says when).
  for (uint64_t k = 1; shadow.contains(line); ++k) {
    ASSERT_LT(k, 64u);
    b.await(access(set_stride * (p.assoc + k)));
  }
  // L is still pending: a lookup merges into its MSHR and installs it again.
  const uint32_t merge = access(line + 8);
  EXPECT_EQ(b.lookups[merge].outcome, Outcome::kMergedMiss);
  EXPECT_EQ(b.lookups[merge].mshr, b.lookups[primary].mshr);
  EXPECT_TRUE(shadow.contains(line));
  const Response rp = b.await(primary);
  EXPECT_EQ(b.await(merge).edge, rp.edge);
  const uint32_t after = access(line + 16);
  EXPECT_EQ(b.lookups[after].outcome, Outcome::kHit) << "installed by the merge";
  EXPECT_EQ(b.mem_requests.size(), size_t(std::count_if(
      b.lookups.begin(), b.lookups.end(),
      [](const auto& l) { return l.second.outcome == Outcome::kPrimaryMiss; })));
}

// Random traffic against a shadow of the spec: outcome priority (pending, tags, free MSHR),
// the lowest free MSHR, one SetAssocCache::access per accepted lookup, refusals only for a full
// set of MSHRs or a held hit, hits answered one edge after acceptance unless held, misses at
// their MSHR's fill edge.
TEST_P(RtlL1Builds, RandomTrafficMatchesTheSpec) {
  const CacheParams p = GetParam().cache();
  Bench b(p);
  SetAssocCache shadow(p);
  std::mt19937_64 rng(42);
  b.latency_fn = [&] { return 1 + static_cast<uint32_t>(rng() % 40); };
  std::map<uint64_t, uint32_t> pending;  // line -> MSHR
  std::array<uint64_t, kMshrs> mshr_line{};
  std::array<bool, kMshrs> busy{};
  std::array<std::vector<uint32_t>, kMshrs> waiting;  // ids
  std::array<uint64_t, kMshrs> last_fill{};           // edge
  std::map<uint32_t, uint64_t> expected_edge;         // id -> answer edge of a miss
  b.on_fill = [&](uint64_t e, uint32_t m) {
    EXPECT_TRUE(busy[m]) << "fill of a free MSHR";
    busy[m] = false;
    pending.erase(mshr_line[m]);
    last_fill[m] = e;
    for (const uint32_t i : waiting[m]) expected_edge[i] = e;
    waiting[m].clear();
  };
  const uint64_t footprint = 2 * p.size_bytes;  // hits, merges and evictions all occur
  uint32_t id = 0;
  uint64_t counts[3] = {};
  for (int cycle = 0; cycle < 60000; ++cycle) {
    if (!b.in.req_valid && rng() % 4 != 0) {
      b.in.req_valid = true;
      b.in.req_addr = (rng() % 3 == 0 ? b.in.req_addr + 8 : rng() % footprint) & ~uint64_t{7};
      b.in.req_id = id & 0xffff;
    }
    b.in.resp_ready = rng() % 8 != 0;
    // The spec's view of this cycle's lookup: the state before its edge.
    const Inputs offered = b.in;
    const uint64_t line = offered.req_addr / p.line_bytes;
    const auto pend = pending.find(line);
    const bool is_pending = pend != pending.end();
    const uint32_t pending_mshr = is_pending ? pend->second : 0;
    const bool present = shadow.contains(offered.req_addr);
    const uint32_t lowest_free =
        static_cast<uint32_t>(std::find(busy.begin(), busy.end(), false) - busy.begin());
    const bool accepted = b.tick();
    if (!offered.req_valid) continue;
    const bool held = b.last.resp_valid && !offered.resp_ready;
    const bool may = is_pending || (present ? !held : lowest_free < kMshrs);
    ASSERT_EQ(accepted, may) << "edge " << b.edge;
    if (!accepted) continue;
    const uint32_t i = offered.req_id;
    const Lookup& l = b.lookups[i];
    if (is_pending) {
      EXPECT_EQ(l.outcome, Outcome::kMergedMiss);
      EXPECT_EQ(l.mshr, pending_mshr);
      if (last_fill[pending_mshr] == b.edge)
        expected_edge[i] = b.edge;  // merged in the fill's cycle
      else
        waiting[pending_mshr].push_back(i);
    } else if (present) {
      EXPECT_EQ(l.outcome, Outcome::kHit);
    } else {
      EXPECT_EQ(l.outcome, Outcome::kPrimaryMiss);
      EXPECT_EQ(l.mshr, lowest_free);
      busy[lowest_free] = true;
      mshr_line[lowest_free] = line;
      pending[line] = lowest_free;
      waiting[lowest_free].push_back(i);
    }
    shadow.access(offered.req_addr);
    ++counts[static_cast<int>(l.outcome)];
    ++id;
    b.in.req_valid = false;
  }
  b.in.req_valid = false;
  b.in.resp_ready = true;
  b.idle(200);
  ASSERT_EQ(b.responses.size(), b.lookups.size());
  std::set<uint32_t> seen;
  for (const Response& r : b.responses) {
    EXPECT_TRUE(seen.insert(r.id).second) << "id " << r.id << " answered twice";
    const Lookup& l = b.lookups[r.id];
    if (l.outcome == Outcome::kHit) {
      EXPECT_GE(r.edge, l.edge + 1) << "id " << r.id;
    } else {
      EXPECT_EQ(r.edge, expected_edge[r.id]) << "id " << r.id;
    }
  }
  EXPECT_EQ(b.mem_requests.size(), counts[static_cast<int>(Outcome::kPrimaryMiss)]);
  EXPECT_GT(counts[static_cast<int>(Outcome::kHit)], 1000u);
  EXPECT_GT(counts[static_cast<int>(Outcome::kMergedMiss)], 100u);
  EXPECT_GT(counts[static_cast<int>(Outcome::kPrimaryMiss)], 1000u);
  std::printf("%s random traffic: %u lookups, %llu hits, %llu primary, %llu merged: %s\n",
              GetParam().model.data(), id, (unsigned long long)counts[0],
              (unsigned long long)counts[1], (unsigned long long)counts[2],
              testing::Test::HasFailure() ? "FAIL" : "PASS");
}

INSTANTIATE_TEST_SUITE_P(Builds, RtlL1Builds, testing::ValuesIn(rtl_l1_builds()), test_name);

}  // namespace
}  // namespace rtusim::rtltest
