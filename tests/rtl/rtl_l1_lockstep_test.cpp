// Lockstep equivalence in blocking mode: every built RTL L1 and SetAssocCache with the same
// parameters, fed the same address stream one access at a time (fill returned at once), must
// agree on the hit/miss outcome of every access: random clustered traces, set-thrashing traces
// that exercise the victim choice, and real kd-tree node traces (built-in Cornell room; the
// kitchen when $RTUSIM_SCENES/kitchen/kitchen.gltf exists).
#include <gtest/gtest.h>

#include "../skip_unless_ci.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "cache/set_assoc_cache.h"
#include "kdtree/sah_builder.h"
#include "layout/dfl_layout.h"
#include "rtl/rtl_l1_registry.h"
#include "rtl_l1_harness.h"
#include "rtl_l1_traces.h"

namespace rtusim::rtltest {
namespace {

std::string build_name(const RtlL1Build& b) {
  std::string s = std::to_string(b.size_bytes) + "_" + std::to_string(b.assoc) + "_" +
                  std::to_string(b.line_bytes) + "_" + std::string(b.policy);
  std::replace(s.begin(), s.end(), '-', '_');
  return s;
}

// Replays `trace` through both; returns the RTL outcomes. Fails at the first disagreement.
std::vector<Outcome> expect_lockstep(const RtlL1Build& b, const std::vector<uint64_t>& trace,
                                     const std::string& what) {
  auto rtl = make_cpp_model(std::string(b.model));
  EXPECT_TRUE(rtl) << "no C++ model for " << b.model;
  if (!rtl) return {};
  SetAssocCache ref(b.cache());
  std::vector<Outcome> out;
  rtl->replay_blocking(trace, out);
  EXPECT_EQ(out.size(), trace.size());
  uint64_t misses = 0;
  for (size_t i = 0; i < trace.size() && i < out.size(); ++i) {
    const bool hit = ref.access(trace[i]);
    misses += hit ? 0 : 1;
    if (hit != (out[i] == Outcome::kHit)) {
      ADD_FAILURE() << what << ": access " << i << " (addr 0x" << std::hex << trace[i] << std::dec
                    << ") is a " << (hit ? "hit" : "miss") << " in SetAssocCache but not in "
                    << b.model;
      return out;
    }
    EXPECT_NE(out[i], Outcome::kMergedMiss);
  }
  EXPECT_EQ(rtl->memory_requests(), misses) << what;
  EXPECT_GT(misses, 0u) << what;
  EXPECT_LT(misses, trace.size()) << what;
  std::printf("%s %s: %zu accesses, %llu misses, identical: %s\n", b.model.data(), what.c_str(),
              trace.size(), static_cast<unsigned long long>(misses),
              ::testing::Test::HasFailure() ? "FAIL" : "PASS");
  return out;
}

class RtlL1Lockstep : public ::testing::TestWithParam<RtlL1Build> {};

TEST_P(RtlL1Lockstep, RandomClusteredTraces) {
  for (uint32_t seed : {1u, 2u, 3u})
    expect_lockstep(GetParam(), clustered_trace(seed, 100000, GetParam().line_bytes),
                    "clustered seed " + std::to_string(seed));
}

TEST_P(RtlL1Lockstep, SetThrashingTraces) {
  // A few more lines than ways in a couple of sets, in random order: every miss evicts.
  const RtlL1Build& b = GetParam();
  for (uint32_t seed : {1u, 2u})
    expect_lockstep(b, set_thrash_trace(seed, 50000, b.size_bytes, b.assoc, b.line_bytes),
                    "set thrash seed " + std::to_string(seed));
}

TEST_P(RtlL1Lockstep, CornellNodeTrace) {
  expect_lockstep(GetParam(), cornell_node_trace(), "cornell node trace");
}

TEST_P(RtlL1Lockstep, KitchenNodeTrace) {
  const std::vector<uint64_t>* t = kitchen_node_trace();
  if (!t) RTUSIM_SKIP_UNLESS_CI("no kitchen scene under $RTUSIM_SCENES");
  expect_lockstep(GetParam(), *t, "kitchen node trace");
}

INSTANTIATE_TEST_SUITE_P(Builds, RtlL1Lockstep, ::testing::ValuesIn(rtl_l1_builds()),
                         [](const ::testing::TestParamInfo<RtlL1Build>& i) {
                           return build_name(i.param);
                         });

// The traces tell the policies apart, so the equivalence above is not vacuous.
TEST(RtlL1LockstepSanity, LruAndTreePlruDifferOnTheThrashTrace) {
  CacheParams lru;  // 8192 / 4 / 64
  CacheParams plru = lru;
  plru.policy = "tree-plru";
  const RtlL1Build* a = find_rtl_l1_build(lru);
  const RtlL1Build* b = find_rtl_l1_build(plru);
  if (!a || !b) RTUSIM_SKIP_UNLESS_CI("needs the 8192/4/64 lru and tree-plru builds");
  const auto trace = set_thrash_trace(1, 20000, 8192, 4, 64);
  std::vector<Outcome> oa, ob;
  make_cpp_model(std::string(a->model))->replay_blocking(trace, oa);
  make_cpp_model(std::string(b->model))->replay_blocking(trace, ob);
  EXPECT_NE(oa, ob);
}

}  // namespace
}  // namespace rtusim::rtltest
