// The host Whitted tracer: secondary rays are traced, both ray orders give the same image,
// and shadows, reflection and refraction behave on hand-made scenes.
#include <gtest/gtest.h>

#include "../skip_unless_ci.h"

#include <cstring>
#include <filesystem>

#include "image/png_writer.h"
#include "kdtree/sah_builder.h"
#include "layout/dfl_layout.h"
#include "scene/builtin_scene.h"
#include "scene/gltf_loader.h"
#include "test_geometry.h"
#include "tracer/host_backend.h"
#include "tracer/whitted_tracer.h"

namespace rtusim {
namespace {

struct Rendered {
  FrameResult frame;
  FetchCounts counts;
};

Rendered render(const Scene& scene, const CameraDesc& cam, TracerParams params, int w, int h) {
  const KdTree tree = build_sah_kd_tree(scene, KdBuildParams{});
  const MemoryImage image = DflLayout().build_image(tree, scene);
  HostBackend backend(image);
  WhittedTracer tracer(scene, params, backend);
  Rendered r;
  r.frame = tracer.render(PinholeCamera(cam, w, h), w, h);
  r.counts = backend.counts();
  return r;
}

TEST(Whitted, RecursiveAndWavefrontGiveTheSameImage) {
  const Scene scene = make_builtin_scene("cornell");
  ASSERT_FALSE(scene.cameras.empty());
  TracerParams p;
  p.order = RayOrder::kRecursive;
  const Rendered a = render(scene, scene.cameras.front(), p, 64, 64);
  p.order = RayOrder::kWavefront;
  const Rendered b = render(scene, scene.cameras.front(), p, 64, 64);
  EXPECT_EQ(a.frame.rays_by_kind, b.frame.rays_by_kind);
  ASSERT_EQ(a.frame.radiance.size(), b.frame.radiance.size());
  EXPECT_EQ(0, std::memcmp(a.frame.radiance.data(), b.frame.radiance.data(),
                           a.frame.radiance.size() * sizeof(glm::vec3)));
  // Same rays, so the same fetch counts (in another order).
  EXPECT_EQ(a.counts.fetches, b.counts.fetches);
  // The builtin scene has a mirror and a glass object: both ray kinds appear.
  EXPECT_GT(a.frame.rays_by_kind[int(RayKind::kReflection)], 0u);
  EXPECT_GT(a.frame.rays_by_kind[int(RayKind::kRefraction)], 0u);
  EXPECT_GT(a.frame.rays_by_kind[int(RayKind::kShadow)], 0u);
  EXPECT_EQ(a.frame.rays_by_kind[int(RayKind::kPrimary)], 64u * 64u);
}

TEST(Whitted, MaxDepthBoundsSecondaryRays) {
  const Scene scene = make_builtin_scene("cornell");
  TracerParams p;
  p.max_depth = 0;
  const Rendered r0 = render(scene, scene.cameras.front(), p, 32, 32);
  EXPECT_EQ(r0.frame.rays_by_kind[int(RayKind::kReflection)], 0u);
  EXPECT_EQ(r0.frame.rays_by_kind[int(RayKind::kRefraction)], 0u);
  p.max_depth = 1;
  const Rendered r1 = render(scene, scene.cameras.front(), p, 32, 32);
  p.max_depth = 4;
  const Rendered r4 = render(scene, scene.cameras.front(), p, 32, 32);
  EXPECT_GT(r1.frame.rays_total(), r0.frame.rays_total());
  EXPECT_GT(r4.frame.rays_total(), r1.frame.rays_total());
}

// A floor with an occluder between it and the light: the shadowed pixel is darker.
TEST(Whitted, ShadowsDarkenOccludedPoints) {
  Scene s;
  testing::add_triangle(s, {-10, 0, -10}, {10, 0, -10}, {0, 0, 10});  // floor at y = 0
  testing::add_triangle(s, {-0.5f, 1, -0.5f}, {0.5f, 1, -0.5f}, {0, 1, 0.5f});  // occluder
  testing::finish(s);
  s.materials[0].metallic = 0.0f;
  s.materials[0].base_color = glm::vec3(0.8f);
  s.lights.push_back(PointLight{"l", {0, 3, 0}, glm::vec3(1.0f), 1.0f});
  TracerParams p;
  p.ambient = 0.0f;
  // Look straight down at the origin (shadowed) and at (3, 0, 0) (lit).
  CameraDesc shadowed{"c", {0, 0.5f, 0}, {0, 0, 0}, {0, 0, 1}, 1.0f};
  CameraDesc lit{"c", {3, 0.5f, 0}, {3, 0, 0}, {0, 0, 1}, 1.0f};
  const Rendered a = render(s, shadowed, p, 1, 1), b = render(s, lit, p, 1, 1);
  EXPECT_EQ(a.frame.radiance[0], glm::vec3(0.0f));
  EXPECT_GT(b.frame.radiance[0].x, 0.1f);
}

// Forwards to the host backend and records every traced ray with its hit.
class RecordingBackend final : public TraceBackend {
 public:
  explicit RecordingBackend(const MemoryImage& image) : host_(image) {}
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override {
    host_.trace(rays, hits);
    for (size_t i = 0; i < rays.size(); ++i) log.emplace_back(rays[i].kind, hits[i]);
  }
  std::vector<std::pair<RayKind, Hit>> log;

 private:
  HostBackend host_;
};

// Tiny scene (7 mm across, like metal_rough_spheres) and a huge one: the scale-aware offset
// keeps secondary rays from re-hitting their own surface, so every refraction ray entering a
// closed glass sphere crosses it (t near its diameter) instead of hitting at t ~ 0.
TEST(Whitted, ScaleAwareOffsetsAvoidSelfIntersection) {
  for (float scale : {1.0f, 0.007f, 1000.0f}) {
    Scene s;
    testing::add_icosphere(s, {0.3f * scale, 0, 0}, 0.5f * scale, 3);
    testing::finish(s);
    s.materials[0].metallic = 0.0f;
    s.materials[0].transmission = 0.5f;  // half diffuse, so shadow rays are cast too
    s.materials[0].ior = 1.5f;
    TracerParams p;
    p.max_depth = 1;
    const KdTree tree = build_sah_kd_tree(s, KdBuildParams{});
    const MemoryImage image = DflLayout().build_image(tree, s);
    RecordingBackend backend(image);
    WhittedTracer tracer(s, p, backend);
    const CameraDesc cam{"c", {0.3f * scale, 0, 3 * scale}, {0.3f * scale, 0, 0}, {0, 1, 0}, 5.0f};
    tracer.render(PinholeCamera(cam, 8, 8), 8, 8);
    int refractions = 0;
    for (const auto& [kind, hit] : backend.log) {
      if (kind == RayKind::kPrimary) EXPECT_TRUE(hit.valid());
      if (kind != RayKind::kRefraction) continue;
      ++refractions;
      ASSERT_TRUE(hit.valid()) << "a refraction ray leaked out of a closed sphere, scale " << scale;
      EXPECT_GT(hit.t, 0.9f * scale) << "self-intersection at scale " << scale;
    }
    EXPECT_EQ(refractions, 64);
    // Shadow rays from the headlight side are not blocked by the surface they start on.
    int lit = 0;
    for (const auto& [kind, hit] : backend.log) lit += kind == RayKind::kShadow && !hit.valid();
    EXPECT_GT(lit, 0);
  }
}

TEST(Whitted, CornellWhittedSceneTracesReflectionAndRefraction) {
  const std::string path = std::string(RTUSIM_SCENES_DEFAULT) + "/cornell_whitted/cornell_whitted.gltf";
  if (!std::filesystem::exists(path)) RTUSIM_SKIP_UNLESS_CI("no shared scenes at " << path);
  const Scene scene = load_gltf(path);
  CameraDesc cam;
  for (const auto& c : scene.cameras)
    if (c.name == "suggested_camera") cam = c;
  ASSERT_EQ(cam.name, "suggested_camera");
  const Rendered r = render(scene, cam, TracerParams{}, 96, 96);
  EXPECT_GT(r.frame.rays_by_kind[int(RayKind::kReflection)], 100u);
  EXPECT_GT(r.frame.rays_by_kind[int(RayKind::kRefraction)], 100u);
  const auto png = std::filesystem::temp_directory_path() / "rtusim_cornell_whitted.png";
  write_png(png.string(), 96, 96, to_srgb8(r.frame.radiance));
  EXPECT_GT(std::filesystem::file_size(png), 1000u);
}

}  // namespace
}  // namespace rtusim
