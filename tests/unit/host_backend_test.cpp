// HostBackend: batched (packet) traversal and its order-free parallel form (ParallelBackend over
// per-thread forks) give the hits and fetch counts of traverse() ray by ray.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include <oneapi/tbb/global_control.h>

#include "kdtree/sah_builder.h"
#include "layout/layout.h"
#include "layout/layout_dispatch.h"
#include "scene/builtin_scene.h"
#include "tracer/host_backend.h"
#include "tracer/parallel_render.h"
#include "traversal/traversal.h"

namespace rtusim {
namespace {

TEST(HostBackend, BatchedAndParallelMatchRayByRay) {
  const Scene scene = make_builtin_scene("cornell");
  const KdTree tree = build_sah_kd_tree(scene, KdBuildParams{});
  const MemoryImage image = make_layout("odfl")->build_image(tree, scene);
  const glm::vec3 lo(image.bounds_min[0], image.bounds_min[1], image.bounds_min[2]);
  const glm::vec3 hi(image.bounds_max[0], image.bounds_max[1], image.bounds_max[2]);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f), u11(-1.0f, 1.0f);
  std::vector<RayRecord> rays(3000);  // several chunks
  for (size_t i = 0; i < rays.size(); ++i) {
    rays[i].ray = {lo + (hi - lo) * glm::vec3(u01(rng), u01(rng), u01(rng)),
                   glm::vec3(u11(rng), u11(rng), i % 9 == 0 ? 0.0f : u11(rng))};
    rays[i].kind = i % 3 == 0 ? RayKind::kShadow : RayKind::kReflection;
    if (i % 3 == 0) rays[i].ray.t_max = 2.0f * u01(rng);
  }
  FetchCounts want;
  std::vector<Hit> want_hits(rays.size());
  with_layout_decoder(image, [&]<class D>() {
    for (size_t i = 0; i < rays.size(); ++i)
      want_hits[i] = traverse<D>(image, rays[i].ray, rays[i].any_hit(), want);
  });
  auto expect_same = [&](const HostBackend& b, const std::vector<Hit>& hits) {
    EXPECT_EQ(b.counts().fetches, want.fetches);
    EXPECT_EQ(b.counts().bytes, want.bytes);
    for (size_t i = 0; i < rays.size(); ++i)
      ASSERT_EQ(std::memcmp(&hits[i], &want_hits[i], sizeof(Hit)), 0) << "ray " << i;
  };
  HostBackend batched(image);
  std::vector<Hit> hits(rays.size());
  batched.trace(rays, hits);
  expect_same(batched, hits);

  tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
  HostBackend host(image);
  ParallelBackend parallel(host);
  std::vector<Hit> parallel_hits(rays.size());
  parallel.trace(rays, parallel_hits);
  expect_same(host, parallel_hits);
}

}  // namespace
}  // namespace rtusim
