// The host-side Whitted tracer: primary rays, shadow rays to every point light, mirror
// reflection and Fresnel refraction up to tracer.max_depth. It issues ray batches to a
// TraceBackend in the configured order (recursive per pixel, or wavefront by generation).
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/pinhole_camera.h"
#include "scene/scene.h"
#include "tracer/trace_backend.h"
#include "tracer/ray_offset.h"
#include "tracer/tracer_params.h"

namespace rtusim {

struct FrameResult {
  int width = 0, height = 0;
  std::vector<glm::vec3> radiance;               // linear RGB per pixel, row-major, y = 0 top
  std::array<uint64_t, kRayKinds> rays_by_kind{};  // traced rays per RayKind
  uint64_t rays_total() const {
    uint64_t n = 0;
    for (auto c : rays_by_kind) n += c;
    return n;
  }
};

class WhittedTracer {
 public:
  WhittedTracer(const Scene& scene, const TracerParams& params, TraceBackend& backend);
  ~WhittedTracer();

  // Renders a frame; the rays reach the backend in the configured order.
  FrameResult render(const PinholeCamera& camera, int width, int height);

  // A frame of black pixels and no rays, for render_pixels.
  FrameResult begin_frame(const PinholeCamera& camera, int width, int height);
  // Traces the ray trees of `pixels` (row-major indices), in this order, into `out`: recursive
  // order one pixel after another, wavefront order as one wavefront over them. render() is
  // begin_frame() and render_pixels() over every pixel in scan order.
  void render_pixels(const PinholeCamera& camera, std::span<const uint32_t> pixels,
                     FrameResult& out);

 private:
  struct PathState;
  struct PathRay;
  struct Spawned;
  struct Wavefront;

  // Shades a hit of `rec`: appends its shadow rays, their terms and its secondary rays to `out`
  // and returns its emission + ambient term.
  glm::vec3 shade(const RayRecord& rec, const PathState& st, const Hit& hit, Spawned& out) const;
  // `base` plus the terms of the unoccluded ones of `n` shadow rays.
  static glm::vec3 local_radiance(glm::vec3 base, const glm::vec3* terms, const Hit* shadow_hits,
                                  size_t n);
  void render_recursive(const PinholeCamera& camera, std::span<const uint32_t> pixels,
                        FrameResult& out);
  void render_wavefront(const PinholeCamera& camera, std::span<const uint32_t> pixels,
                        FrameResult& out);
  void trace_recursive(const PathRay& pr, FrameResult& out, glm::vec3& acc);

  const Scene& scene_;
  TracerParams params_;
  TraceBackend& backend_;
  RayOffset offset_;
  std::vector<PointLight> lights_;  // the scene's, or the headlight
  std::vector<uint64_t> key_step_;  // ray-tree key stride per depth (preorder keys)
  // Reused buffers (no allocation per ray): the recursive order's spawned rays per depth, and
  // the wavefront order's generation buffers.
  std::vector<Spawned> recursive_spawned_;
  std::unique_ptr<Wavefront> wavefront_;
};

}  // namespace rtusim
