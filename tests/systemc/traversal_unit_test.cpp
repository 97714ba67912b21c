// Traversal unit timing, exactly: one ray in flight against memories of fixed latency, the
// cycle count replayed by hand from the same step function's fetches; and the stack-depth and
// pipeline counters.
#include <gtest/gtest.h>

#include <random>

#include "kdtree/sah_builder.h"
#include "layout/dfl_layout.h"
#include "model/host_interface.h"
#include "model/traversal_unit.h"
#include "sc_fixture.h"
#include "test_geometry.h"
#include "tlm_test_modules.h"
#include "traversal/traversal.h"
#include "util/stats.h"

namespace rtusim {
namespace {

constexpr uint64_t kCycle = 1000;
constexpr uint64_t kNodeLatency = 30, kDataLatency = 45;  // cycles

struct Rec {
  struct F {
    Stream s;
    uint64_t addr;
    uint32_t bytes;
  };
  std::vector<F> f;
  void fetch(Stream s, uint64_t a, uint32_t b) { f.push_back({s, a, b}); }
};

struct Fixture {
  Scene scene;
  KdTree tree;
  MemoryImage image;
  std::vector<RayRecord> rays;
  Fixture() {
    scene = testing::random_soup(3, 300);
    testing::finish(scene);
    tree = build_sah_kd_tree(scene, KdBuildParams{});
    image = DflLayout().build_image(tree, scene);
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 40; ++i) {
      RayRecord r;
      r.ray.origin = glm::vec3(u(rng), u(rng), -3.0f);
      r.ray.dir = glm::vec3(u(rng) * 0.3f, u(rng) * 0.3f, 1.0f);
      r.kind = i % 5 == 4 ? RayKind::kShadow : RayKind::kPrimary;
      rays.push_back(r);
    }
  }
};

struct Top {
  HostInterface host;
  TraversalUnit unit;
  testing::FixedLatencyMemory node_mem, data_mem;
  Top(const UnitParams& p, const MemoryImage& image)
      : host("host"), unit("unit", p, image, host),
        node_mem("node_mem", kNodeLatency * kCycle, false),
        data_mem("data_mem", kDataLatency * kCycle, false) {
    unit.node_socket.bind(node_mem.socket);
    unit.data_socket.bind(data_mem.socket);
  }
};

UnitParams unit_params() {
  UnitParams p;
  p.rays_in_flight = 1;
  p.clock_period_ps = kCycle;
  p.step_cycles = 3;
  p.stack_depth = 2;
  p.isect_lanes = 1;
  p.isect_latency_cycles = 7;
  p.isect_interval_cycles = 2;
  p.node_line_bytes = 64;
  p.data_line_bytes = 64;
  return p;
}

// The cycles one ray in flight takes, from the timing rules in traversal_unit.h.
struct Expected {
  uint64_t cycles = 0, steps = 0, deep_steps = 0, node_requests = 0, data_requests = 0;
};
Expected replay(const Fixture& f, const UnitParams& p) {
  Expected e;
  uint64_t t = 0;
  auto lines = [](const Rec::F& x) { return (x.addr + x.bytes - 1) / 64 - x.addr / 64 + 1; };
  for (const RayRecord& r : f.rays) {
    TraversalState s;
    traversal_begin(s, f.image, r.ray, r.any_hit());
    while (!s.done) {
      Rec rec;
      const StepKind k = traversal_step<DflLayout>(s, f.image, rec);
      ++e.steps;
      e.deep_steps += s.sp > static_cast<int>(p.stack_depth);
      e.node_requests += 1;
      t += kNodeLatency + p.step_cycles;  // the node, then the step
      if (k == StepKind::kLeaf) {
        size_t first = 1;
        if (rec.f.size() > 1 && rec.f[1].s == Stream::kList) {
          e.data_requests += lines(rec.f[1]);
          t += kDataLatency;
          first = 2;
        }
        const uint64_t n = rec.f.size() - first;
        if (n > 0) {
          for (size_t i = first; i < rec.f.size(); ++i) e.data_requests += lines(rec.f[i]);
          t += kDataLatency + (n - 1) * p.isect_interval_cycles + p.isect_latency_cycles;
        }
      }
    }
  }
  e.cycles = t;
  return e;
}

class TraversalUnitTest : public testing::SystemCTest {};

TEST_F(TraversalUnitTest, OneRayInFlightTakesTheReplayedCycles) {
  Fixture f;
  const UnitParams p = unit_params();
  const Expected e = replay(f, p);
  Top top(p, f.image);
  std::vector<Hit> hits(f.rays.size());
  top.host.post(f.rays, hits);
  sc_core::sc_start();
  ASSERT_TRUE(top.host.batch_done());
  EXPECT_EQ(sc_core::sc_time_stamp().value(), e.cycles * kCycle);
  EXPECT_EQ(top.unit.steps(), e.steps);
  EXPECT_EQ(top.node_mem.arrivals.size(), e.node_requests);
  EXPECT_EQ(top.data_mem.arrivals.size(), e.data_requests);
  for (const auto& a : top.data_mem.arrivals) {
    EXPECT_EQ(a.addr % 64, 0u);  // whole lines
    EXPECT_EQ(a.bytes, 64u);
  }
  Stats s;
  top.unit.write_stats(s);
  EXPECT_EQ(s.at("unit.stack_overflow_steps").get<uint64_t>(), e.deep_steps);
  EXPECT_GT(e.deep_steps, 0u);  // the test means something
  for (size_t i = 0; i < f.rays.size(); ++i) {
    NullFetchSink sink;
    EXPECT_EQ(hits[i].triangle,
              traverse<DflLayout>(f.image, f.rays[i].ray, f.rays[i].any_hit(), sink).triangle);
  }
}

TEST_F(TraversalUnitTest, ManyRaysShareTheStepPipeline) {
  Fixture f;
  UnitParams p = unit_params();
  p.rays_in_flight = 16;
  Top top(p, f.image);
  std::vector<Hit> hits(f.rays.size());
  top.host.post(f.rays, hits);
  sc_core::sc_start();
  ASSERT_TRUE(top.host.batch_done());
  const uint64_t cycles = sc_core::sc_time_stamp().value() / kCycle;
  // At most one step per cycle, and far fewer cycles than one ray at a time.
  EXPECT_GE(cycles, top.unit.steps());
  EXPECT_LT(cycles * 4, replay(f, p).cycles);
  // Every step's cycle is distinct: steps never exceed the cycles the pipeline had.
  Stats s;
  top.unit.write_stats(s);
  EXPECT_EQ(s.at("unit.rays").get<uint64_t>(), f.rays.size());
}

}  // namespace
}  // namespace rtusim
