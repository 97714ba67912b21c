// RayStepLog: a recorded ray gives back the traversal's hit and, step by step, its fetches and
// whether each step was a leaf, as traversal_step() reports them.
#include "tier/ray_step_log.h"

#include <gtest/gtest.h>

#include <random>
#include <tuple>
#include <vector>

#include "kdtree/sah_builder.h"
#include "layout/dfl_layout.h"
#include "test_geometry.h"
#include "traversal/fetch_recorder.h"

namespace rtusim {
namespace {

using Fetch = std::tuple<int, uint64_t, uint32_t, bool>;  // stream, address, bytes, leaf node

TEST(RayStepLogTest, RecordsEveryStepsFetchesAndTheHit) {
  const Scene scene = testing::random_soup(5, 2000);
  const KdTree tree = build_sah_kd_tree(scene, KdBuildParams{});
  const MemoryImage image = DflLayout().build_image(tree, scene);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.5f, 1.5f);
  RayStepLog log;
  std::vector<std::vector<Fetch>> expected;
  std::vector<Hit> hits;
  size_t leaves = 0, lists = 0, misses = 0;
  for (uint32_t i = 0; i < 400; ++i) {
    RayRecord r;
    r.ray.origin = {u(rng), u(rng), u(rng)};
    r.ray.dir = glm::normalize(glm::vec3{u(rng), u(rng), u(rng)});
    if (i % 50 == 0) r.ray.origin = {10, 10, 10};  // some miss the scene's bounds
    r.kind = i % 3 == 0 ? RayKind::kShadow : RayKind::kPrimary;
    r.pixel = i * 7;
    // The reference: traversal_step() with a recorder, step by step.
    TraversalState s;
    traversal_begin(s, image, r.ray, r.any_hit());
    std::vector<Fetch> want;
    while (!s.done) {
      std::vector<RecordedFetch> step;
      FetchRecorder rec{&step};
      const bool leaf = traversal_step<DflLayout>(s, image, rec) == StepKind::kLeaf;
      for (size_t k = 0; k < step.size(); ++k)
        want.emplace_back(int(step[k].stream), step[k].addr, step[k].bytes, k == 0 && leaf);
      leaves += leaf;
      lists += step.size() > 1 && step[1].stream == Stream::kList;
    }
    misses += want.empty();
    expected.push_back(want);
    hits.push_back(log.record<DflLayout>(image, r));
    EXPECT_EQ(hits.back().t, s.hit.t);
    EXPECT_EQ(hits.back().triangle, s.hit.triangle);
  }
  ASSERT_EQ(log.ray_count(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(log.pixel(i), i * 7);
    const std::span<const uint64_t> words = log.ray(i);
    std::vector<Fetch> got;
    for (const uint64_t* p = words.data(); p != words.data() + words.size();) {
      const bool node = RayStepLog::is_node(*p);
      const RayStepLog::Fetch f = RayStepLog::next(p);
      EXPECT_EQ(node, f.stream() == Stream::kNode);
      got.emplace_back(int(f.stream()), f.addr, f.bytes, f.kind == RayStepLog::Kind::kLeaf);
    }
    EXPECT_EQ(got, expected[i]) << "ray " << i;
  }
  EXPECT_GT(leaves, 400u);
  EXPECT_GT(lists, 10u);
  EXPECT_GT(misses, 3u);
  log.clear();
  EXPECT_EQ(log.ray_count(), 0u);
}

}  // namespace
}  // namespace rtusim
