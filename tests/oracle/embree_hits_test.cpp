// Primary hits of the kd-tree traversal against Embree on the shared scenes: hit/miss agreement
// >= 99.9% and t within 1e-4 relative where both hit.
#include <gtest/gtest.h>

#include "../skip_unless_ci.h"

#include <cmath>
#include <filesystem>

#include "embree_scene.h"
#include "kdtree/sah_builder.h"
#include "layout/dfl_layout.h"
#include "scene/gltf_loader.h"
#include "scene/pinhole_camera.h"
#include "traversal/traversal.h"

namespace rtusim {
namespace {

struct Case {
  const char* scene;
  const char* camera;
};

class EmbreeHits : public ::testing::TestWithParam<Case> {};

TEST_P(EmbreeHits, PrimaryHitsAgree) {
  const Case c = GetParam();
  const char* env = std::getenv("RTUSIM_SCENES");
  const std::string dir = env && *env ? env : RTUSIM_SCENES_DEFAULT;
  const std::string path = dir + "/" + c.scene + "/" + c.scene + ".gltf";
  if (!std::filesystem::exists(path)) RTUSIM_SKIP_UNLESS_CI("no scene " << path);

  const Scene scene = load_gltf(path);
  const KdTree tree = build_sah_kd_tree(scene, KdBuildParams{});
  const MemoryImage image = DflLayout().build_image(tree, scene);
  oracle::EmbreeScene embree(scene);
  CameraDesc cam;
  for (const auto& k : scene.cameras)
    if (k.name == c.camera) cam = k;
  ASSERT_EQ(cam.name, c.camera);

  const int w = 256, h = 256;
  const PinholeCamera camera(cam, w, h);
  int disagree = 0, both = 0, t_off = 0, same_tri_off = 0, hits = 0;
  double worst_rel = 0.0;
  NullFetchSink sink;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Ray r = camera.generate(x, y);
      const Hit a = traverse<DflLayout>(image, r, false, sink);
      const Hit b = embree.intersect(r);
      hits += a.valid();
      if (a.valid() != b.valid()) {
        ++disagree;
        continue;
      }
      if (!a.valid()) continue;
      ++both;
      const double rel = std::abs(double(a.t) - b.t) / std::max(1e-30, std::abs(double(b.t)));
      worst_rel = std::max(worst_rel, rel);
      if (a.triangle == b.triangle) same_tri_off += rel > 1e-4;
      else t_off += rel > 1e-4;  // another surface at the same pixel (edge, coplanar faces)
    }
  const double agreement = 1.0 - double(disagree) / (w * h);
  RecordProperty("agreement", std::to_string(agreement));
  std::printf("%s: %d hits, hit/miss agreement %.5f, %d of %d t beyond 1e-4 (worst %.2e)\n",
              c.scene, hits, agreement, t_off, both, worst_rel);
  EXPECT_GT(hits, w * h / 20) << "the camera must see the scene";
  EXPECT_GE(agreement, 0.999);
  // Where both hit the same triangle, t agrees to 1e-4 relative, always.
  EXPECT_EQ(same_tri_off, 0);
  // Where they hit different triangles at one pixel (shared edges, coplanar overlapping
  // faces), t may differ only within the same 0.1% budget.
  EXPECT_LE(double(t_off) / std::max(both, 1), 0.001);
}

INSTANTIATE_TEST_SUITE_P(SharedScenes, EmbreeHits,
                         ::testing::Values(Case{"box", "suggested_camera"},
                                           Case{"cornell_whitted", "suggested_camera"},
                                           Case{"sponza_dabrovic", "atrium_view"},
                                           Case{"kitchen", "bart_camera_t0"},
                                           Case{"iridescent_dish", "Camera001_from_source"},
                                           Case{"metal_rough_spheres", "front_view"}),
                         [](const auto& info) { return std::string(info.param.scene); });

}  // namespace
}  // namespace rtusim
