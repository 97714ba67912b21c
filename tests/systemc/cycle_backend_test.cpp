// The cycle tier end to end on hand-built scenes: hits equal the host backend's for every
// layout, and with one ray in flight the DRAM bytes equal the functional tier's (FetchCache fed
// by the same traversal over the same rays in the same order). Plus the config keys.
#include <gtest/gtest.h>

#include <random>

#include "cache/fetch_cache.h"
#include "config/config_reader.h"
#include "kdtree/sah_builder.h"
#include "layout/layout.h"
#include "layout/layout_dispatch.h"
#include "mem/dram/dram.h"
#include "mem/l1_cache.h"
#include "model/cycle_backend.h"
#include "model/cycle_params.h"
#include "sc_fixture.h"
#include "scene_fixture.h"
#include "test_geometry.h"
#include "tracer/host_backend.h"
#include "traversal/traversal.h"
#include "util/error.h"
#include "util/stats.h"

namespace rtusim {
namespace {

using testing::SceneFixture;

void expect_same_hits(const std::vector<Hit>& a, const std::vector<Hit>& b) {
  ASSERT_EQ(a.size(), b.size());
  int valid = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].triangle, b[i].triangle) << "ray " << i;
    ASSERT_EQ(a[i].t, b[i].t) << "ray " << i;
    ASSERT_EQ(a[i].u, b[i].u) << "ray " << i;
    ASSERT_EQ(a[i].v, b[i].v) << "ray " << i;
    valid += a[i].valid();
  }
  EXPECT_GT(valid, static_cast<int>(a.size() / 4));  // the rays do hit things
}

CycleParams default_params() {
  CycleParams p;
  p.finish();
  return p;
}

class CycleBackendTest : public testing::SystemCTest,
                         public ::testing::WithParamInterface<std::string> {};

TEST_P(CycleBackendTest, HitsEqualTheHostBackend) {
  SceneFixture f(GetParam());
  CycleParams p = default_params();
  p.data_cache = p.node_l1;  // lists and triangles through their own cache
  p.finish();
  CycleBackend cycle(f.image, p);
  HostBackend host(f.image);
  std::vector<Hit> hc(f.rays.size()), hh(f.rays.size());
  // Two batches: time and counters accumulate.
  const std::span<const RayRecord> all(f.rays);
  const size_t half = f.rays.size() / 2;
  cycle.trace(all.first(half), std::span<Hit>(hc).first(half));
  const uint64_t cycles_first = cycle.cycles();
  cycle.trace(all.subspan(half), std::span<Hit>(hc).subspan(half));
  host.trace(all, hh);
  expect_same_hits(hc, hh);
  EXPECT_GT(cycle.cycles(), cycles_first);
  EXPECT_GT(cycles_first, 0u);

  Stats s;
  cycle.write_stats(s);
  const FetchCounts& fc = host.counts();
  EXPECT_EQ(s.at("traversal.node_fetches").get<uint64_t>(), fc.fetches[0]);
  EXPECT_EQ(s.at("l1.accesses").get<uint64_t>(), fc.fetches[0]);  // nodes never span lines
  EXPECT_EQ(s.at("l1.accesses").get<uint64_t>(),
            s.at("l1.hits").get<uint64_t>() + s.at("l1.misses").get<uint64_t>());
  EXPECT_EQ(s.at("l1.misses").get<uint64_t>(), s.at("l1.primary_misses").get<uint64_t>() +
                                                    s.at("l1.merged_misses").get<uint64_t>());
  EXPECT_EQ(s.at("dram.bytes.nodes").get<uint64_t>(), cycle.node_l1().bytes_from_dram());
  EXPECT_EQ(s.at("dram.bytes.total").get<uint64_t>(),
            s.at("dram.bytes.nodes").get<uint64_t>() + s.at("dram.bytes.lists").get<uint64_t>() +
                s.at("dram.bytes.triangles").get<uint64_t>());
  for (const char* key : {"sim.cycles", "sim.rays_per_second", "dram.gbytes_per_second",
                          "l1.mshr_stall_cycles", "l1.mean_miss_latency_cycles",
                          "unit.utilisation", "dram.row_hit_rate", "dcache.hits"})
    EXPECT_TRUE(s.has(key)) << key;
  EXPECT_GT(s.at("unit.utilisation").get<double>(), 0.0);
  EXPECT_LE(s.at("unit.utilisation").get<double>(), 1.0);
  EXPECT_GT(s.at("l1.mean_miss_latency_cycles").get<double>(), 20.0);  // DRAM takes > 20 ns
}

INSTANTIATE_TEST_SUITE_P(Layouts, CycleBackendTest, ::testing::Values("dfl", "odfl", "subtree"),
                         [](const ::testing::TestParamInfo<std::string>& i) { return i.param; });

// With one ray in flight the unit issues the functional tier's fetches in the same order, so
// the caches see the same sequence and DRAM moves the same bytes.
class OneRayInFlightTest : public testing::SystemCTest,
                           public ::testing::WithParamInterface<bool> {};

TEST_P(OneRayInFlightTest, DramBytesEqualTheFunctionalTier) {
  const bool dcache = GetParam();
  SceneFixture f("odfl");
  CycleParams p = default_params();
  p.unit.rays_in_flight = 1;
  p.node_l1.cache.size_bytes = 2048;  // small, so misses and evictions are many
  if (dcache) {
    p.data_cache = p.node_l1;
    p.data_cache->cache.size_bytes = 4096;
    p.data_cache->cache.line_bytes = 32;
  }
  p.finish();
  CycleBackend cycle(f.image, p);
  std::vector<Hit> hits(f.rays.size());
  cycle.trace(f.rays, hits);

  FetchCacheParams fp;
  fp.node_l1 = p.node_l1.cache;
  if (dcache) fp.data_cache = p.data_cache->cache;
  FetchCache functional(fp);
  with_layout_decoder(f.image, [&]<class Decoder>() {
    for (size_t i = 0; i < f.rays.size(); ++i) {
      const Hit h = traverse<Decoder>(f.image, f.rays[i].ray, f.rays[i].any_hit(), functional);
      ASSERT_EQ(h.triangle, hits[i].triangle);
    }
  });

  Stats s;
  cycle.write_stats(s);
  EXPECT_EQ(s.at("dram.bytes.nodes").get<uint64_t>(), functional.stream(Stream::kNode).dram_bytes);
  EXPECT_EQ(s.at("l1.hits").get<uint64_t>(), functional.node_l1().hits());
  EXPECT_EQ(s.at("l1.primary_misses").get<uint64_t>(), functional.node_l1().misses());
  EXPECT_EQ(s.at("l1.merged_misses").get<uint64_t>(), 0u);
  EXPECT_EQ(s.at("dram.bytes.lists").get<uint64_t>(), functional.stream(Stream::kList).dram_bytes);
  EXPECT_EQ(s.at("dram.bytes.triangles").get<uint64_t>(),
            functional.stream(Stream::kTriangle).dram_bytes);
  EXPECT_GT(functional.stream(Stream::kNode).dram_bytes, 0u);
}

INSTANTIATE_TEST_SUITE_P(DataPath, OneRayInFlightTest, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& i) {
                           return i.param ? "DataCache" : "StraightToDram";
                         });

// More rays in flight hide memory latency: the same rays take fewer cycles.
class LatencyHidingTest : public testing::SystemCTest,
                          public ::testing::WithParamInterface<uint32_t> {};

uint64_t cycles_with(uint32_t rays_in_flight) {
  SceneFixture f("dfl");
  CycleParams p = default_params();
  p.unit.rays_in_flight = rays_in_flight;
  p.finish();
  CycleBackend cycle(f.image, p);
  std::vector<Hit> hits(f.rays.size());
  cycle.trace(f.rays, hits);
  return cycle.cycles();
}

TEST_F(LatencyHidingTest, ThirtyTwoRaysBeatOne) {
  const uint64_t one = cycles_with(1);
  const uint64_t many = cycles_with(32);  // a second backend in the same process
  EXPECT_LT(many * 4, one) << "1 ray: " << one << " cycles, 32 rays: " << many;
}

// Each backend has its own SystemC context: backends built one after another in one process
// (as a multi-layout run or `rtusim regress` does) start at cycle 0 and repeat exactly.
TEST(CycleBackendContexts, SequentialBackendsInOneProcessRepeatExactly) {
  SceneFixture f("odfl");
  std::vector<uint64_t> cycles;
  std::vector<std::vector<Hit>> hits;
  for (int run = 0; run < 3; ++run) {
    CycleBackend cycle(f.image, default_params());
    hits.emplace_back(f.rays.size());
    cycle.trace(f.rays, hits.back());
    cycles.push_back(cycle.cycles());
  }
  EXPECT_GT(cycles[0], 0u);
  EXPECT_EQ(cycles[0], cycles[1]);
  EXPECT_EQ(cycles[1], cycles[2]);
  expect_same_hits(hits[0], hits[2]);
}

TEST(CycleParamsTest, DefaultsAndKeys) {
  ConfigReader r = ConfigReader::from_string(
      "[sim]\nrays_in_flight = 4\nclock_mhz = 500.0\n[l1]\nmshrs = 2\n[dram]\n"
      "standard = \"DDR4-3200\"\nchannels = 2\n",
      "test.toml");
  const CycleParams p = read_cycle_params(r);
  r.reject_unknown_keys();
  EXPECT_EQ(p.unit.rays_in_flight, 4u);
  EXPECT_EQ(p.unit.clock_period_ps, 2000u);
  EXPECT_EQ(p.node_l1.clock_period_ps, 2000u);
  EXPECT_EQ(p.node_l1.mshrs, 2u);
  EXPECT_EQ(p.node_l1.hit_cycles, 2u);
  EXPECT_EQ(p.node_l1.cache.size_bytes, 8192u);
  EXPECT_FALSE(p.data_cache.has_value());
  EXPECT_EQ(p.unit.data_line_bytes, 64u);  // DRAM bursts
  EXPECT_EQ(p.dram.channels, 2u);
  EXPECT_EQ(p.dram.data_rate_mts, 3200u);
  EXPECT_DOUBLE_EQ(p.dram.tRCD_ns, 13.75);

  ConfigReader bad = ConfigReader::from_string("[isect]\nlanes = 0\n", "bad.toml");
  try {
    read_cycle_params(bad);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("isect.lanes"), std::string::npos) << e.what();
  }
  ConfigReader deep = ConfigReader::from_string("[sim]\nstack_depth = 65\n", "deep.toml");
  EXPECT_THROW(read_cycle_params(deep), InputError);
}

}  // namespace
}  // namespace rtusim
