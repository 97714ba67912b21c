// The hand-built scene of the cycle-tier end-to-end tests (a random triangle soup around an
// icosphere, a SAH kd-tree, one layout's memory image, 1500 mixed rays), shared by
// tests/systemc/cycle_backend_test.cpp and tests/rtl/rtl_l1_adapter_test.cpp.
#pragma once
#include <random>
#include <string>
#include <vector>

#include "kdtree/sah_builder.h"
#include "layout/layout.h"
#include "test_geometry.h"
#include "tracer/trace_backend.h"

namespace rtusim::testing {

struct SceneFixture {
  Scene scene;
  KdTree tree;
  MemoryImage image;
  std::vector<RayRecord> rays;

  explicit SceneFixture(const std::string& layout) {
    scene = random_soup(7, 600);
    add_icosphere(scene, glm::vec3(0.2f, -0.3f, 0.1f), 0.4f, 2);
    finish(scene);
    tree = build_sah_kd_tree(scene, KdBuildParams{});
    image = make_layout(layout)->build_image(tree, scene);
    // Rays from outside and inside the soup, closest-hit and shadow (any-hit), some missing.
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.5f, 1.5f);
    for (int i = 0; i < 1500; ++i) {
      RayRecord r;
      r.ray.origin = i % 3 == 0 ? glm::vec3(u(rng), u(rng), u(rng)) * 0.5f
                                : glm::vec3(u(rng), u(rng), -3.0f);
      r.ray.dir = glm::vec3(u(rng), u(rng), u(rng) + (i % 3 == 0 ? 0.0f : 3.0f));
      if (i % 4 == 3) {
        r.kind = RayKind::kShadow;
        r.ray.t_max = 0.8f;
      }
      r.pixel = static_cast<uint32_t>(i);
      rays.push_back(r);
    }
  }
};

}  // namespace rtusim::testing
