// Kd-tree traversal as one step function, shared by the host tracer and the SystemC unit.
// Front-to-back, stack-based (pbrt's three cases), reading every node, list and triangle from
// the memory image and reporting each fetch to a sink, in issue order.
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>

#include <glm/vec3.hpp>
#if defined(__SSE4_1__)
#include <smmintrin.h>
#endif

#include "geom/ray.h"
#include "kdtree/kd_tree.h"
#include "layout/memory_image.h"
#include "layout/node_view.h"
#include "traversal/watertight_triangle.h"

namespace rtusim {

// A fetch sink that drops everything: plain traversal with no memory model.
struct NullFetchSink {
  void fetch(Stream, uint64_t /*addr*/, uint32_t /*bytes*/) {}
};

enum class StepKind : uint8_t {
  kInterior,  // visited an interior node (one node fetch)
  kLeaf,      // visited a leaf and tested its triangles
  kDone,      // nothing left: the hit (if any) is final
};

// The state of one ray in traversal: what a hardware unit keeps per ray in flight.
struct TraversalState {
  // Entries the stack can need: each entry is the far child of one interior node on the path
  // to the node being visited, so there are never more than that node's depth, and no node is
  // deeper than the builder's limit.
  static constexpr int kStackDepth = 64;
  static_assert(kStackDepth >= KdBuildParams::kMaxDepthLimit);
  struct Entry {
    uint64_t addr;
    float t_min, t_max;
  };

  Ray ray;
  bool any_hit = false;  // shadow rays: stop at the first hit in (0, t_max)
  // Per axis, as plain arrays (a glm::vec3 indexed by a run-time axis is a switch): origin,
  // direction, 1/direction and |1/direction|.
  float org[3] = {0, 0, 0}, dir[3] = {0, 0, 1}, inv_dir[3] = {0, 0, 1}, abs_inv_dir[3] = {0, 0, 1};
  // Per axis, the origin for the side test: the origin itself where the direction is positive
  // (or NaN), else the next float below it, so that `org_side < split` says "below first": the
  // origin is below the plane, or on it and heading down (or parallel).
  float org_side[3] = {0, 0, 0};
  WatertightRay wray;
  uint64_t node = 0;  // node to visit next
  float t_min = 0.0f, t_max = 0.0f;
  Entry stack[kStackDepth];
  int sp = 0;
  bool done = false;
  Hit hit;
  uint32_t leaf_prims_tested = 0;  // of the last leaf step: triangles intersected
};

// The largest float below x (std::nextafter(x, -inf) without the library call).
inline float next_float_down(float x) {
  if (x == 0.0f) return -std::numeric_limits<float>::denorm_min();
  if (x == -std::numeric_limits<float>::infinity() || std::isnan(x)) return x;
  uint32_t b;
  std::memcpy(&b, &x, sizeof b);
  b = x > 0.0f ? b - 1 : b + 1;
  std::memcpy(&x, &b, sizeof b);
  return x;
}

// Starts a ray: clips it to the scene bounds; a ray that misses them is done at once.
inline void traversal_begin(TraversalState& s, const MemoryImage& image, const Ray& ray,
                            bool any_hit) {
  s.ray = ray;
  s.any_hit = any_hit;
  s.hit = Hit{};
  s.sp = 0;
  s.node = image.root_addr;
  s.wray = WatertightRay(ray.origin, ray.dir);
  // Per axis: 1/direction (+-inf for a zero component, handled below), the side-test origin,
  // and where the ray crosses the scene's slab, widened by a few ulps so rounding never clips a
  // hit on the scene's boundary.
  constexpr float kWidenIn = 1.0f - 6.0f * std::numeric_limits<float>::epsilon();
  constexpr float kWidenOut = 1.0f + 6.0f * std::numeric_limits<float>::epsilon();
  float slab_in[4], slab_out[4];
#if defined(__SSE4_1__)
  // The three axes in three lanes at once: lane by lane the same float operations as the
  // scalar version below, so the same values.
  {
    const __m128 zero = _mm_setzero_ps();
    const __m128 o = _mm_setr_ps(ray.origin.x, ray.origin.y, ray.origin.z, 0.0f);
    const __m128 d = _mm_setr_ps(ray.dir.x, ray.dir.y, ray.dir.z, 1.0f);
    const __m128 inv = _mm_div_ps(_mm_set1_ps(1.0f), d);
    // next_float_down(o): one ulp towards -inf, -denorm_min for a zero, -inf and NaN kept.
    const __m128 up = _mm_cmpgt_ps(o, zero);  // all ones (-1) where the bits step down
    __m128 down = _mm_castsi128_ps(_mm_add_epi32(
        _mm_castps_si128(o), _mm_or_si128(_mm_castps_si128(up), _mm_set1_epi32(1))));
    const __m128 keep = _mm_or_ps(
        _mm_cmpeq_ps(o, _mm_set1_ps(-std::numeric_limits<float>::infinity())),
        _mm_cmpunord_ps(o, o));
    down = _mm_blendv_ps(down, o, keep);
    down = _mm_blendv_ps(down, _mm_set1_ps(-std::numeric_limits<float>::denorm_min()),
                         _mm_cmpeq_ps(o, zero));
    const __m128 side = _mm_blendv_ps(o, down, _mm_cmple_ps(d, zero));
    const __m128 bmin = _mm_setr_ps(image.bounds_min[0], image.bounds_min[1],
                                    image.bounds_min[2], 0.0f);
    const __m128 bmax = _mm_setr_ps(image.bounds_max[0], image.bounds_max[1],
                                    image.bounds_max[2], 0.0f);
    const __m128 tn = _mm_mul_ps(_mm_sub_ps(bmin, o), inv);
    const __m128 tf = _mm_mul_ps(_mm_sub_ps(bmax, o), inv);
    const __m128 swap = _mm_cmpgt_ps(tn, tf);
    _mm_storeu_ps(slab_in, _mm_mul_ps(_mm_blendv_ps(tn, tf, swap), _mm_set1_ps(kWidenIn)));
    _mm_storeu_ps(slab_out, _mm_mul_ps(_mm_blendv_ps(tf, tn, swap), _mm_set1_ps(kWidenOut)));
    float inv4[4], abs4[4], side4[4];
    _mm_storeu_ps(inv4, inv);
    _mm_storeu_ps(abs4, _mm_andnot_ps(_mm_set1_ps(-0.0f), inv));
    _mm_storeu_ps(side4, side);
    for (int a = 0; a < 3; ++a) {
      s.org[a] = ray.origin[a];
      s.dir[a] = ray.dir[a];
      s.inv_dir[a] = inv4[a];
      s.abs_inv_dir[a] = abs4[a];
      s.org_side[a] = side4[a];
    }
  }
#else
  for (int a = 0; a < 3; ++a) {
    s.org[a] = ray.origin[a];
    s.dir[a] = ray.dir[a];
    s.inv_dir[a] = 1.0f / ray.dir[a];
    s.abs_inv_dir[a] = std::abs(s.inv_dir[a]);
    s.org_side[a] = ray.dir[a] <= 0.0f ? next_float_down(ray.origin[a]) : ray.origin[a];
    float tn = (image.bounds_min[a] - ray.origin[a]) * s.inv_dir[a];
    float tf = (image.bounds_max[a] - ray.origin[a]) * s.inv_dir[a];
    if (tn > tf) std::swap(tn, tf);
    slab_in[a] = tn * kWidenIn;
    slab_out[a] = tf * kWidenOut;
  }
#endif
  // The scene's bounds clip the ray, axis by axis; a ray parallel to an axis is clipped away
  // when its origin lies outside that slab.
  float t0 = 0.0f, t1 = ray.t_max;
  for (int a = 0; a < 3; ++a) {
    const float o = ray.origin[a];
    if (ray.dir[a] == 0.0f) {
      if (o < image.bounds_min[a] || o > image.bounds_max[a]) t1 = -1.0f;
      continue;
    }
    t0 = std::max(t0, slab_in[a]);
    t1 = std::min(t1, slab_out[a]);
  }
  s.t_min = t0;
  s.t_max = t1;
  s.done = !(t0 <= t1) || image.nodes.size_bytes == 0;
}

namespace detail {
// Pops the next node whose interval can still hold a closer hit; false if none is left.
[[gnu::always_inline]] inline bool traversal_pop(TraversalState& s) {
  while (s.sp > 0) {
    const TraversalState::Entry& e = s.stack[--s.sp];
    if (e.t_min > s.hit.t) continue;  // everything there is farther than the hit found
    s.node = e.addr;
    s.t_min = e.t_min;
    s.t_max = e.t_max;
    return true;
  }
  return false;
}

// An interior node's step: the next node, and the far child pushed when the ray sees both.
[[gnu::always_inline]] inline void interior_step(TraversalState& s, const NodeView& n) {
  // Interior: which side the origin is on (a branch the predictor gets right, so the next
  // node's fetch need not wait for the arithmetic below), and where the ray crosses the plane.
  const int a = n.axis;
  const float o = s.org[a], d = s.dir[a];
  const bool below_first = s.org_side[a] < n.split;
  const uint64_t near = below_first ? n.below_addr : n.above_addr;
  const uint64_t far = below_first ? n.above_addr : n.below_addr;
  const float t_plane = (n.split - o) * s.inv_dir[a];
  // Decisions are conservative by the rounding error of t_plane (the operands' ulps, in t,
  // plus a relative margin; |t_plane| <= (|split| + |o|) |1/d|, so one product bounds
  // both): a ray that passes through a leaf's closed box, even at one corner point, visits
  // it, so hits on shared edges and vertices never slip between leaves.
  const float slack = (std::abs(n.split) + std::abs(o)) * s.abs_inv_dir[a] * 0x1p-19f;
  // Behind the origin first: that test needs no slack, so its branch resolves sooner.
  if (t_plane <= 0.0f || t_plane - slack > s.t_max) {
    s.node = near;  // the plane lies behind the origin or beyond the interval
    return;
  }
  if (t_plane + slack < s.t_min) {
    s.node = far;  // the ray enters the interval already past the plane
    return;
  }
  // A ray parallel to the plane (or 0 * inf) lands here or goes near above, where the parallel
  // case would have sent it too: t_plane is NaN (every comparison false), +inf (slack is +inf,
  // so t_plane - slack is NaN) or -inf (t_plane <= 0, and the origin is off the plane).
  // Here d == 0 makes t_plane +inf or NaN, so one cheap test on t_plane guards the exact one.
  if (!(t_plane < std::numeric_limits<float>::infinity())) [[unlikely]] {
    if (d == 0.0f || std::isnan(t_plane)) {
      // Parallel to the plane: a ray in the plane sees both sides, else one.
      if (o == n.split) {
        s.stack[s.sp++] = {n.above_addr, s.t_min, s.t_max};
        s.node = n.below_addr;
      } else {
        s.node = near;
      }
      return;
    }
  }
  s.stack[s.sp++] = {far, std::max(s.t_min, t_plane - slack), s.t_max};
  s.node = near;
  s.t_max = std::min(s.t_max, t_plane + slack);
}

// Fetches the ray's next node (reported to the sink) and decodes it from the image.
template <class Decoder, class Sink>
[[gnu::always_inline]] inline NodeView fetch_node(const TraversalState& s, const MemoryImage& image,
                                                  Sink& sink) {
  sink.fetch(Stream::kNode, s.node, image.node_bytes);
  return Decoder::decode(image, s.node);
}

// Floats stored at a byte address of the image, read one by one where they lie.
struct PackedFloats {
  const uint8_t* bytes;
  float operator[](int i) const {
    float f;
    std::memcpy(&f, bytes + 4 * i, sizeof f);
    return f;
  }
};

// One triangle's watertight test (`test(t_limit, t, u, v)`) within the hit found so far;
// records a hit and returns true on one.
template <class Test>
[[gnu::always_inline]] inline bool record_hit(Hit& hit, float ray_t_max, uint32_t tri,
                                              Test&& test) {
  float t, bu, bv;
  if (!test(std::min(hit.t, ray_t_max), t, bu, bv)) return false;
  hit = {t, tri, bu, bv};
  return true;
}

// A leaf's triangle id `i`, from its node or its list.
[[gnu::always_inline]] inline uint32_t leaf_triangle(const MemoryImage& image, const NodeView& n,
                                                     uint32_t i) {
  uint32_t tri = n.inline_prim;
  if (n.prim_count > 1) std::memcpy(&tri, image.bytes.data() + n.list_addr + 4ull * i, sizeof tri);
  return tri;
}

// What a leaf's triangles leave besides the hit: how many were tested, whether the ray is done
// (any-hit mode).
struct LeafTested {
  uint32_t tested;
  bool done;
};

// Tests a leaf's triangles one by one against `hit` (a ray's parts: its watertight form, hit so
// far, own t_max, any-hit mode), each fetched (reported) just before its test.
template <class Sink>
[[gnu::always_inline]] inline LeafTested leaf_triangles_loop(const WatertightRay& wray, Hit& hit,
                                                             float ray_t_max, bool any_hit,
                                                             const MemoryImage& image,
                                                             const NodeView& n, Sink& sink) {
  for (uint32_t i = 0; i < n.prim_count; ++i) {
    const uint32_t tri = leaf_triangle(image, n, i);
    const uint64_t ta = image.triangle_addr(tri);
    sink.fetch(Stream::kTriangle, ta, MemoryImage::kTriangleBytes);
    const PackedFloats v{image.bytes.data() + ta};
    if (record_hit(hit, ray_t_max, tri, [&](float t_limit, float& t, float& bu, float& bv) {
          return intersect_watertight(wray, v, t_limit, t, bu, bv);
        }) && any_hit)
      return {i + 1, true};
  }
  return {n.prim_count, false};
}

// A leaf's list (if any) and triangles, fetched and tested against `hit` (a ray's parts, as in
// leaf_triangles_loop()), one by one (an AVX-512 test of 16 triangles at a time was slower on
// AMD EPYC Zen 5: docs/speed_notes.md). Shared by the single-ray step and the packets' lanes.
template <class Sink>
[[gnu::always_inline]] inline LeafTested leaf_triangles(const WatertightRay& wray, Hit& hit,
                                                        float ray_t_max, bool any_hit,
                                                        const MemoryImage& image,
                                                        const NodeView& n, Sink& sink) {
  if (n.prim_count >= 2) sink.fetch(Stream::kList, n.list_addr, n.prim_count * 4u);
  return leaf_triangles_loop(wray, hit, ray_t_max, any_hit, image, n, sink);
}

// A leaf's step: fetches its list (if any) and triangles, tests each, then pops or finishes.
template <class Sink>
[[gnu::always_inline]] inline void leaf_step(TraversalState& s, const MemoryImage& image,
                                             const NodeView& n, Sink& sink) {
  const LeafTested o = leaf_triangles(s.wray, s.hit, s.ray.t_max, s.any_hit, image, n, sink);
  s.leaf_prims_tested = o.tested;
  // The ray is finished in this leaf when its hit lies inside the leaf's interval, or (any-hit)
  // when it found one.
  if (o.done || s.hit.t <= s.t_max || !traversal_pop(s)) s.done = true;
}
}  // namespace detail

// Visits one node of ray `s`. `Decoder` is the layout's static decode(image, addr) -> NodeView.
template <class Decoder, class Sink>
[[gnu::always_inline]] inline StepKind traversal_step(TraversalState& s, const MemoryImage& image,
                                                      Sink& sink) {
  if (s.done) return StepKind::kDone;
  const NodeView n = detail::fetch_node<Decoder>(s, image, sink);
  if (!n.leaf) [[likely]] {
    detail::interior_step(s, n);
    return StepKind::kInterior;
  }
  detail::leaf_step(s, image, n, sink);
  return StepKind::kLeaf;
}

// Traverses a whole ray; returns its closest hit (or first hit in any-hit mode).
template <class Decoder, class Sink = NullFetchSink>
inline Hit traverse(const MemoryImage& image, const Ray& ray, bool any_hit, Sink& sink) {
  TraversalState s;
  traversal_begin(s, image, ray, any_hit);
  // The step function's visits, as an inner descent loop over interior nodes and one leaf.
  while (!s.done) {
    NodeView n = detail::fetch_node<Decoder>(s, image, sink);
    while (!n.leaf) {
      detail::interior_step(s, n);
      n = detail::fetch_node<Decoder>(s, image, sink);
    }
    detail::leaf_step(s, image, n, sink);
  }
  return s.hit;
}

}  // namespace rtusim
