// RayStepLog: a recorded ray gives back the traversal's hit and, step by step, its fetches and
// whether each step was a leaf, as traversal_step() reports them; fetches too large or too far
// for one word come back from the three-word form exactly.
#include "traversal/ray_step_log.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <iterator>
#include <random>
#include <tuple>
#include <vector>

#include "kdtree/sah_builder.h"
#include "layout/dfl_layout.h"
#include "layout/node_view.h"
#include "test_geometry.h"
#include "tracer/trace_backend.h"
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
    std::vector<int> want_sp;  // the stack depth after each step
    while (!s.done) {
      FetchList step;
      const bool leaf = traversal_step<DflLayout>(s, image, step) == StepKind::kLeaf;
      want_sp.push_back(s.sp);
      for (size_t k = 0; k < step.size(); ++k)
        want.emplace_back(int(step[k].stream), step[k].addr, step[k].bytes, k == 0 && leaf);
      leaves += leaf;
      lists += step.size() > 1 && step[1].stream == Stream::kList;
    }
    misses += want.empty();
    expected.push_back(want);
    std::vector<int> got_sp;  // record()'s after_step sees each step's state
    hits.push_back(
        log.record<DflLayout>(image, r, [&](const TraversalState& st) { got_sp.push_back(st.sp); }));
    EXPECT_EQ(got_sp, want_sp) << "ray " << i;
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

// A chain of interior nodes at addresses on both sides of the one-word form's limit (2^43), each
// sending every ray on to the next, ending in a leaf whose list is the image's list region.
struct ChainDecoder {
  static constexpr uint64_t kFarStart = uint64_t{1} << 43;  // first address of the long form
  static constexpr uint64_t kChain[] = {0,
                                        kFarStart - 64,
                                        kFarStart - 1,
                                        kFarStart,
                                        kFarStart + 64,
                                        ~uint64_t{0},
                                        0x0123456789abcdefull,
                                        128};
  static constexpr size_t kLength = std::size(kChain);
  static NodeView decode(const MemoryImage& image, uint64_t addr) {
    NodeView n;
    const size_t i = std::find(kChain, kChain + kLength, addr) - kChain;
    if (i + 1 < kLength) {
      n.leaf = false;
      n.axis = 2;
      n.split = 1e6f;  // beyond the scene's bounds: the ray goes on to the near child
      n.below_addr = n.above_addr = kChain[i + 1];
      return n;
    }
    n.prim_count = static_cast<uint32_t>(image.lists.size_bytes / 4);
    n.list_addr = image.lists.base_addr;
    return n;
  }
};

TEST(RayStepLogTest, LongFetchesComeBackExactly) {
  // The one-word form holds bytes below 2^19 - 1 and addresses below 2^43. Per image, node bytes
  // and a leaf of `prims` triangles (all triangle 0, which the ray misses; list bytes 4 * prims)
  // on either side of the bytes limit.
  struct Case {
    uint32_t node_bytes, prims;
  };
  const Case cases[] = {{8, 2},                    // all short but the far addresses
                        {(1u << 19) - 2, 131071},  // node bytes 2^19 - 2, list 2^19 - 4: short
                        {(1u << 19) - 1, 131072},  // node bytes 2^19 - 1, list 2^19: long
                        {1u << 19, 0},             // an empty leaf
                        {0xffffffffu, 1}};         // the triangle's id in the leaf node
  const float far_vertices[9] = {5, 5, 5, 6, 5, 5, 5, 6, 5};
  RayStepLog log;
  std::vector<std::vector<Fetch>> expected;
  for (const Case& c : cases) {
    MemoryImage image;
    image.node_bytes = c.node_bytes;
    image.nodes = {0, 64};
    image.root_addr = ChainDecoder::kChain[0];
    image.triangles = {0, MemoryImage::kTriangleBytes};
    image.lists = {64, 4ull * c.prims};
    image.bytes.assign(image.lists.end_addr(), 0);
    std::memcpy(image.bytes.data(), far_vertices, sizeof far_vertices);
    for (int a = 0; a < 3; ++a) {
      image.bounds_min[a] = -1.0f;
      image.bounds_max[a] = 1.0f;
    }
    RayRecord r;
    r.ray.origin = {0, 0, 0};
    r.ray.dir = {0, 0, 1};
    r.kind = RayKind::kPrimary;
    EXPECT_FALSE(log.record<ChainDecoder>(image, r).valid());
    std::vector<Fetch> want;
    for (size_t i = 0; i < ChainDecoder::kLength; ++i)
      want.emplace_back(int(Stream::kNode), ChainDecoder::kChain[i], c.node_bytes,
                        i + 1 == ChainDecoder::kLength);
    if (c.prims > 1) want.emplace_back(int(Stream::kList), 64, 4 * c.prims, false);
    for (uint32_t k = 0; k < c.prims; ++k)
      want.emplace_back(int(Stream::kTriangle), 0, MemoryImage::kTriangleBytes, false);
    expected.push_back(want);
  }
  ASSERT_EQ(log.ray_count(), expected.size());
  size_t long_words = 0;
  for (size_t i = 0; i < expected.size(); ++i) {
    const std::span<const uint64_t> words = log.ray(i);
    const uint64_t* const end = words.data() + words.size();
    std::vector<Fetch> got;
    for (const uint64_t* p = words.data(); p < end;) {
      const bool node = RayStepLog::is_node(*p);
      const uint64_t* const first = p;
      const RayStepLog::Fetch f = RayStepLog::next(p);
      long_words += p - first == 3;
      EXPECT_EQ(node, f.stream() == Stream::kNode);
      got.emplace_back(int(f.stream()), f.addr, f.bytes, f.kind == RayStepLog::Kind::kLeaf);
    }
    ASSERT_EQ(got.size(), expected[i].size()) << "ray " << i;
    for (size_t k = 0; k < got.size(); ++k)
      ASSERT_EQ(got[k], expected[i][k]) << "ray " << i << " fetch " << k;
  }
  // The long form was taken where it must be: the four far nodes of the two rays with short node
  // bytes, every node of the three with long ones, and the list of 2^19 bytes.
  EXPECT_EQ(long_words, 2 * 4 + 3 * ChainDecoder::kLength + 1);
}

}  // namespace
}  // namespace rtusim
