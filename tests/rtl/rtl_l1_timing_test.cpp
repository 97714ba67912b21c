// The RTL L1's non-blocking behaviour and exact cycle counts (default build: 8192 B, 4-way,
// 64 B, lru, 8 MSHRs, 8 targets, hit latency 1, 4 response entries), as l1_cache.sv documents
// them: hit and miss latency, secondary-miss merging, MSHR-full and target-full stalls, the
// fill cycle's stall, response back-pressure; and a random stress with several misses in flight
// checked against a shadow model of the documented semantics built on the C++ policies.
#include <gtest/gtest.h>

#include <cstdio>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "cache/replacement_policy.h"
#include "rtl/rtl_l1_registry.h"
#include "rtl_l1_harness.h"

namespace rtusim::rtltest {
namespace {

constexpr uint32_t kMshrs = 8, kTargets = 8, kRespDepth = 4;

struct Response {
  uint64_t edge;
  uint32_t id;
  Outcome outcome;
};

// Cycle-by-cycle driver with a memory of configurable latency: a fill request accepted at edge
// k is answered by i_mem_resp_valid in the cycle ending at edge k + latency (one fill per cycle).
class Bench {
 public:
  explicit Bench(const CacheParams& p = CacheParams{}, uint32_t mem_latency = 10)
      : m_(make_cpp_model(std::string(rtl_l1_build(p).model))), latency_(mem_latency) {}

  Inputs in;                        // request side inputs, driven every cycle
  std::vector<Response> responses;  // in the order they left
  std::vector<uint64_t> mem_requests;
  uint64_t edge = 0;
  std::function<uint32_t()> latency_fn;  // per request; default the fixed latency
  // Called with (edge, line address) for every fill, at the edge that installs it.
  std::function<void(uint64_t, uint64_t)> on_fill;

  // One cycle: drive, sample, rising edge. Returns whether the offered request was accepted.
  bool tick() {
    Inputs drive = in;
    drive.mem_resp_valid = false;
    if (!fills_.empty() && fills_.begin()->first <= edge + 1) {
      drive.mem_resp_valid = true;
      drive.mem_resp_addr = fills_.begin()->second;
    }
    m_->drive(drive);
    last = m_->outputs();
    last_in = drive;
    const bool accepted = drive.req_valid && last.req_ready;
    ++edge;
    if (last.resp_valid && drive.resp_ready)
      responses.push_back({edge, last.resp_id,
                           last.resp_hit      ? Outcome::kHit
                           : last.resp_merged ? Outcome::kMergedMiss
                                              : Outcome::kPrimaryMiss});
    if (last.mem_req_valid && drive.mem_req_ready) {
      mem_requests.push_back(last.mem_req_addr);
      const uint32_t l = latency_fn ? latency_fn() : latency_;
      // Due edges are kept unique: memory returns one fill per cycle.
      uint64_t due = edge + l;
      while (fills_.count(due)) ++due;
      fills_.emplace(due, last.mem_req_addr);
    }
    if (drive.mem_resp_valid) {
      if (on_fill) on_fill(edge, drive.mem_resp_addr);
      fills_.erase(fills_.begin());
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

  // Runs until the response for `id` has left; returns it.
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

  Outputs last;
  Inputs last_in;

 private:
  std::unique_ptr<RtlL1Model> m_;
  uint32_t latency_;
  std::map<uint64_t, uint64_t> fills_;  // due edge -> line address
};

TEST(RtlL1Timing, HitIsAnsweredOneCycleAfterAcceptance) {
  Bench b;
  b.request(0x4000, 1);
  b.await(1);
  const uint64_t a = b.request(0x4020, 2);
  const Response r = b.await(2);
  EXPECT_EQ(r.outcome, Outcome::kHit);
  EXPECT_EQ(r.edge - a, 1u);
  // Back-to-back hits: one accepted and one answered per cycle.
  const uint64_t first = b.edge + 1;
  for (uint32_t i = 0; i < 16; ++i) EXPECT_EQ(b.request(0x4000 + 4 * i, 10 + i), first + i);
  b.idle(2);
  for (uint32_t i = 0; i < 16; ++i) {
    const Response h = b.await(10 + i);
    EXPECT_EQ(h.outcome, Outcome::kHit);
    EXPECT_EQ(h.edge, first + i + 1);
  }
  EXPECT_EQ(b.mem_requests.size(), 1u);
}

TEST(RtlL1Timing, MissIsAnsweredLPlusThreeCyclesAfterAcceptance) {
  for (uint32_t latency : {1u, 2u, 10u, 100u}) {
    Bench b(CacheParams{}, latency);
    const uint64_t a = b.request(0x12345, 7);
    const Response r = b.await(7);
    EXPECT_EQ(r.outcome, Outcome::kPrimaryMiss);
    EXPECT_EQ(r.edge - a, latency + 3) << "memory latency " << latency;
    ASSERT_EQ(b.mem_requests.size(), 1u);
    EXPECT_EQ(b.mem_requests[0], 0x12340u) << "the line's first byte";
  }
}

TEST(RtlL1Timing, SecondaryMissesMergeIntoOneMemoryRequest) {
  Bench b(CacheParams{}, 20);
  const uint64_t a = b.request(0x8000, 1);
  EXPECT_EQ(b.request(0x8008, 2), a + 1);
  EXPECT_EQ(b.request(0x8030, 3), a + 2);
  const Response r1 = b.await(1), r2 = b.await(2), r3 = b.await(3);
  EXPECT_EQ(b.mem_requests.size(), 1u);
  EXPECT_EQ(r1.outcome, Outcome::kPrimaryMiss);
  EXPECT_EQ(r2.outcome, Outcome::kMergedMiss);
  EXPECT_EQ(r3.outcome, Outcome::kMergedMiss);
  EXPECT_EQ(r1.edge, a + 20 + 3);
  EXPECT_EQ(r2.edge, r1.edge + 1);
  EXPECT_EQ(r3.edge, r1.edge + 2);
  // Afterwards the line hits.
  b.request(0x8010, 4);
  EXPECT_EQ(b.await(4).outcome, Outcome::kHit);
}

TEST(RtlL1Timing, StallsForANewPrimaryMissWhenAllMshrsAreBusy) {
  Bench b(CacheParams{}, 50);
  b.request(0x100000, 100);  // a line to hit later
  b.await(100);
  uint64_t a0 = 0;
  for (uint32_t i = 0; i < kMshrs; ++i) {
    const uint64_t a = b.request(0x200000 + 0x1000 * i, i);
    if (i == 0) a0 = a;
    EXPECT_EQ(a, a0 + i) << "misses accepted back to back while MSHRs are free";
  }
  b.tick();
  EXPECT_EQ(b.last.mshrs_busy, kMshrs);
  // A new primary miss is refused while every MSHR is busy...
  b.in = Inputs{};
  b.in.req_valid = true;
  b.in.req_addr = 0x300000;
  b.in.req_id = 50;
  for (int i = 0; i < 10; ++i) EXPECT_FALSE(b.tick()) << "cycle " << i;
  b.in.req_valid = false;
  // ...but a hit and a merge into a pending line still go through.
  const uint64_t ah = b.request(0x100008, 51);
  EXPECT_EQ(b.await(51).edge, ah + 1);
  b.request(0x203000, 52);
  // The refused miss is accepted at the first cycle with a free MSHR and no fill.
  b.in.req_valid = true;
  b.in.req_addr = 0x300000;
  b.in.req_id = 50;
  bool accepted = false;
  for (int i = 0; i < 200 && !accepted; ++i) {
    accepted = b.tick();
    const bool may = b.last.mshrs_busy < kMshrs && !b.last_in.mem_resp_valid;
    EXPECT_EQ(b.last.req_ready, may) << "edge " << b.edge;
  }
  b.in.req_valid = false;
  EXPECT_TRUE(accepted);
  EXPECT_EQ(b.await(52).outcome, Outcome::kMergedMiss);
  EXPECT_EQ(b.await(50).outcome, Outcome::kPrimaryMiss);
  EXPECT_EQ(b.mem_requests.size(), 1u + kMshrs + 1u);
}

TEST(RtlL1Timing, StallsAMergeWhenTheMshrTargetsAreFull) {
  Bench b(CacheParams{}, 30);
  for (uint32_t i = 0; i < kTargets; ++i) b.request(0x5000 + 4 * i, i);
  b.in.req_valid = true;
  b.in.req_addr = 0x5000;
  b.in.req_id = 99;
  uint64_t fill_edge = 0;
  b.on_fill = [&](uint64_t e, uint64_t) { fill_edge = e; };
  bool accepted = false;
  while (!accepted) {
    accepted = b.tick();
    if (!accepted) {
      EXPECT_FALSE(b.last.req_ready);
    }
    if (fill_edge) {
      EXPECT_TRUE(accepted || b.last_in.mem_resp_valid);
    }
    if (fill_edge && b.last_in.mem_resp_valid) {
      EXPECT_FALSE(b.last.req_ready) << "fill cycle";
    }
  }
  b.in.req_valid = false;
  EXPECT_EQ(b.edge, fill_edge + 1) << "accepted the cycle after the fill";
  EXPECT_EQ(b.await(99).outcome, Outcome::kHit);
  for (uint32_t i = 0; i < kTargets; ++i)
    EXPECT_EQ(b.await(i).outcome, i == 0 ? Outcome::kPrimaryMiss : Outcome::kMergedMiss);
  EXPECT_EQ(b.mem_requests.size(), 1u);
}

TEST(RtlL1Timing, ResponseBackPressureStopsHitsAfterTheQueueFills) {
  Bench b;
  b.request(0x7000, 1);
  b.await(1);
  b.in.resp_ready = false;
  for (uint32_t i = 0; i < kRespDepth; ++i) b.request(0x7000, 10 + i);
  b.in.req_valid = true;
  b.in.req_addr = 0x7000;
  b.in.req_id = 20;
  for (int i = 0; i < 5; ++i) EXPECT_FALSE(b.tick());
  b.in.resp_ready = true;
  EXPECT_FALSE(b.tick()) << "the pop frees a credit for the next cycle";
  EXPECT_TRUE(b.tick());
  b.in.req_valid = false;
  b.idle(8);
  ASSERT_EQ(b.responses.size(), 2u + kRespDepth);
  for (uint32_t i = 0; i < kRespDepth; ++i) EXPECT_EQ(b.responses[1 + i].id, 10 + i);
  EXPECT_EQ(b.responses.back().id, 20u);
}

// Shadow of the documented semantics: lookup at acceptance (hit touches), install + touch at the
// fill edge (lowest invalid way, else the C++ policy's victim), merged requests never touch.
class Shadow {
 public:
  explicit Shadow(const CacheParams& p)
      : sets_(static_cast<uint32_t>(p.sets())), ways_(p.assoc), line_bytes_(p.line_bytes),
        policy_(make_replacement_policy(p.policy, sets_, ways_, 1)),
        tags_(uint64_t{sets_} * ways_, ~uint64_t{0}), filled_(sets_, 0) {}

  Outcome access(uint64_t addr) {
    const uint64_t line = addr / line_bytes_;
    const uint32_t set = static_cast<uint32_t>(line % sets_);
    for (uint32_t w = 0; w < ways_; ++w)
      if (tags_[uint64_t{set} * ways_ + w] == line) {
        policy_->touch(set, w);
        return Outcome::kHit;
      }
    if (pending_.count(line)) return Outcome::kMergedMiss;
    pending_.insert(line);
    return Outcome::kPrimaryMiss;
  }
  void fill(uint64_t addr) {
    const uint64_t line = addr / line_bytes_;
    const uint32_t set = static_cast<uint32_t>(line % sets_);
    EXPECT_EQ(pending_.erase(line), 1u) << "fill of a line not pending";
    const uint32_t way = filled_[set] < ways_ ? filled_[set]++ : policy_->victim(set);
    tags_[uint64_t{set} * ways_ + way] = line;
    policy_->fill(set, way);
  }

 private:
  uint32_t sets_, ways_, line_bytes_;
  std::unique_ptr<ReplacementPolicy> policy_;
  std::vector<uint64_t> tags_;
  std::vector<uint32_t> filled_;
  std::set<uint64_t> pending_;
};

class RtlL1Stress : public testing::TestWithParam<RtlL1Build> {};

TEST_P(RtlL1Stress, RandomTrafficMatchesTheDocumentedSemantics) {
  const RtlL1Build& build = GetParam();
  CacheParams p;
  p.size_bytes = build.size_bytes;
  p.assoc = build.assoc;
  p.line_bytes = build.line_bytes;
  p.policy = std::string(build.policy);
  Bench b(p);
  Shadow shadow(p);
  std::mt19937_64 rng(42);
  b.latency_fn = [&] { return 1 + static_cast<uint32_t>(rng() % 40); };
  std::map<uint32_t, Outcome> expected;
  b.on_fill = [&](uint64_t, uint64_t addr) { shadow.fill(addr); };
  // A small footprint (about 2x the cache) in clusters, so hits, merges and evictions all occur.
  const uint64_t footprint = 2 * p.size_bytes;
  uint32_t id = 0;
  uint64_t merged = 0, primary = 0, hits = 0;
  b.in.req_valid = false;
  for (int cycle = 0; cycle < 60000; ++cycle) {
    if (!b.in.req_valid && rng() % 4 != 0) {
      b.in.req_valid = true;
      b.in.req_addr = (rng() % 3 == 0 ? b.in.req_addr + 8 : rng() % footprint) & ~uint64_t{7};
      b.in.req_id = id & 0xffff;
    }
    b.in.resp_ready = rng() % 8 != 0;
    const Inputs offered = b.in;
    if (b.tick()) {
      // The fill (if any) of this edge came first in on_fill only when it was not a fill
      // cycle, which the RTL guarantees (o_req_ready is low in a fill cycle).
      const Outcome o = shadow.access(offered.req_addr);
      expected[offered.req_id] = o;
      (o == Outcome::kHit ? hits : o == Outcome::kMergedMiss ? merged : primary)++;
      ++id;
      b.in.req_valid = false;
    }
  }
  b.in.req_valid = false;
  b.in.resp_ready = true;
  b.idle(200);
  ASSERT_EQ(b.responses.size(), expected.size());
  std::set<uint32_t> seen;
  for (const Response& r : b.responses) {
    EXPECT_TRUE(seen.insert(r.id).second) << "id " << r.id << " answered twice";
    EXPECT_EQ(r.outcome, expected[r.id]) << "id " << r.id;
  }
  EXPECT_EQ(b.mem_requests.size(), primary);
  EXPECT_GT(hits, 1000u);
  EXPECT_GT(merged, 100u);
  EXPECT_GT(primary, 1000u);
  std::printf("%s stress: %u requests, %llu hits, %llu primary, %llu merged: %s\n",
              build.model.data(), id, static_cast<unsigned long long>(hits),
              static_cast<unsigned long long>(primary), static_cast<unsigned long long>(merged),
              testing::Test::HasFailure() ? "FAIL" : "PASS");
}

INSTANTIATE_TEST_SUITE_P(Builds, RtlL1Stress, testing::ValuesIn(rtl_l1_builds()),
                         [](const testing::TestParamInfo<RtlL1Build>& i) {
                           std::string s(i.param.model);
                           for (char& c : s) c = c == '-' ? '_' : c;
                           return s;
                         });

}  // namespace
}  // namespace rtusim::rtltest
