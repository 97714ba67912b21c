// Up to 8 rays (AVX2, and AVX-512 hosts too) traversing the kd-tree together: one node fetch
// and decode, and one vector step, serve every ray that visits the node. Each ray's result is
// the single-ray one: its hit bit for bit, and its own fetches (node, list, triangle) in the
// order traverse() reports them for that ray alone.
//
// Why it is exact: at an interior node every lane computes traverse()'s own float operations
// (same expressions, same order, std::min/std::max written as their comparisons) and so takes
// the same case: near only, far only, or both (far pushed with the far interval). The packet
// visits the below child with the below-first lanes' near set, then the above child with the
// below-first lanes' far set and the above-first lanes' near set, then the below child again
// with the above-first lanes' far set (lanes that agree leave one of these empty), so each
// lane's visits keep its single-ray order. A lane that would go straight to one child waits
// out the other's subtree inactive, its hit unchanged; the pop test (entry t_min > hit t) then
// cannot drop it, since a ray's current t_min never exceeds its hit's t. Stack entries carry a
// lane mask; a lane finished in a leaf leaves the live mask. Leaves test each lane with the
// single-ray leaf code, or (8 lanes, two or more active) each triangle against the active lanes
// at once with WatertightLanes8 (each lane the single-ray test's float operations; its rare
// double-precision cases with the single-ray code): a lane's triangles in leaf order, each one
// reported to that lane just before its test, stopping at an any-hit lane's first hit, as the
// single-ray loop does. Lanes the packet does not take (admits() false) go through traverse().
// The lane width is a parameter (`Simd`: PacketSimd8, the operations on 8 floats; 16 lanes on
// AVX-512 were slower, see docs/speed_notes.md); an inactive lane's interval values are never
// read, so they may be anything.
#pragma once
#if defined(__AVX2__)
#define RTUSIM_RAY_PACKETS 1
#include <cstdint>

#include "traversal/packet_simd8.h"
#include "traversal/traversal.h"
#include "traversal/watertight_lanes8.h"

namespace rtusim {

template <class Simd>
class BasicRayPacket {
 public:
  static constexpr int kLanes = Simd::kLanes;

  // What a packet traversal did (for tests).
  struct Stats {
    uint64_t mixed_splits = 0;  // interior steps whose lanes disagreed on the near side
    uint64_t lane_leaves = 0;   // leaves whose triangles were tested against the lanes at once
    uint64_t lane_scalar_tests = 0;  // of their lane tests, those done with the single-ray code
  };

  // Whether a ray may be a lane: a finite origin and every direction component nonzero and
  // finite with a finite reciprocal, so that no lane ever meets traverse()'s parallel case
  // (d == 0 or a NaN t_plane; split positions are finite).
  static bool admits(const Ray& ray) {
    for (int a = 0; a < 3; ++a) {
      const float o = ray.origin[a], d = ray.dir[a];
      if (!std::isfinite(o) || !std::isfinite(d) || d == 0.0f || !std::isfinite(1.0f / d))
        return false;
    }
    return true;
  }

  // Empties the packet.
  void clear() { live_ = 0; }

  // Sets lane `lane` to ray `ray` (admits(ray) true), as traversal_begin() starts it.
  void set_lane(int lane, const MemoryImage& image, const Ray& ray, bool any_hit) {
    TraversalState s;
    traversal_begin(s, image, ray, any_hit);
    for (int a = 0; a < 3; ++a) {
      org_[a][lane] = s.org[a];
      inv_dir_[a][lane] = s.inv_dir[a];
      abs_inv_dir_[a][lane] = s.abs_inv_dir[a];
      org_side_[a][lane] = s.org_side[a];
    }
    wray_[lane] = s.wray;
    wlanes_.set_lane(lane, s.wray);
    ray_t_max_[lane] = ray.t_max;
    t_min_[lane] = s.t_min;
    t_max_[lane] = s.t_max;
    set_hit(lane, s.hit);
    const uint32_t bit = 1u << lane;
    any_hit_ = any_hit ? any_hit_ | bit : any_hit_ & ~bit;
    live_ = s.done ? live_ & ~bit : live_ | bit;
  }

  Hit hit(int lane) const { return {hit_t_[lane], hit_tri_[lane], hit_u_[lane], hit_v_[lane]}; }
  const Stats& stats() const { return stats_; }

  // Traverses the live lanes to the end. `lanes.lane(i)` is lane i's fetch sink (the single-ray
  // sink interface), and `Lanes::kDropsFetches` says that all of them drop every fetch;
  // `Decoder` is the layout's static decode(image, addr) -> NodeView.
  template <class Decoder, class Lanes>
  void traverse(const MemoryImage& image, Lanes& lanes);

 private:
  // Entries: at most two per interior node on the path to the node being visited.
  static constexpr int kStackDepth = 2 * TraversalState::kStackDepth;
  using Vec = typename Simd::Vec;
  using Mask = typename Simd::Mask;
  // Leaves test a triangle against the lanes at once (WatertightLanes8: 8 lanes) from this
  // many active lanes.
  static_assert(kLanes == 8, "the lanes' leaf test is 8 wide");
  static constexpr int kLeafLanesMin = 2;
  struct Entry {
    Vec t_min, t_max;  // per lane: the interval in the child
    uint64_t addr;     // the child
    Mask lanes;        // the lanes that visit it
  };

  // Reports the node fetch of every lane in `active`.
  template <class Lanes>
  static void report_node(const MemoryImage& image, uint64_t node, Mask active, Lanes& lanes) {
    if constexpr (!Lanes::kDropsFetches)
      for (uint32_t m = Simd::bits(active); m != 0; m &= m - 1)
        lanes.lane(__builtin_ctz(m)).fetch(Stream::kNode, node, image.node_bytes);
  }

  // Tests a leaf's triangles for every lane in `active` (their intervals end at t_max_); lanes
  // that finish here leave the live mask.
  template <class Lanes>
  void leaf(const MemoryImage& image, const NodeView& n, Mask active, Lanes& lanes);
  // The same for a leaf with triangles, each tested against the active lanes at once.
  template <class Lanes>
  void leaf_lanes(const MemoryImage& image, const NodeView& n, Mask active, Lanes& lanes);

  void set_hit(int lane, const Hit& h) {
    hit_t_[lane] = h.t;
    hit_tri_[lane] = h.triangle;
    hit_u_[lane] = h.u;
    hit_v_[lane] = h.v;
  }

  alignas(64) float org_[3][kLanes], inv_dir_[3][kLanes], abs_inv_dir_[3][kLanes];
  alignas(64) float org_side_[3][kLanes];  // TraversalState::org_side
  alignas(64) float t_min_[kLanes], t_max_[kLanes];  // at set_lane(); the leaf's interval
  // Each lane's hit so far: t, triangle, u, v.
  alignas(64) float hit_t_[kLanes], hit_u_[kLanes], hit_v_[kLanes];
  alignas(64) uint32_t hit_tri_[kLanes];
  alignas(64) float ray_t_max_[kLanes];
  WatertightRay wray_[kLanes];
  WatertightLanes8 wlanes_;
  uint32_t any_hit_ = 0;  // lanes in any-hit mode
  uint32_t live_ = 0;     // lanes not finished
  Stats stats_;
};

template <class Simd>
template <class Lanes>
void BasicRayPacket<Simd>::leaf(const MemoryImage& image, const NodeView& n, Mask active,
                                Lanes& lanes) {
  if (n.prim_count == 0) {
    // An empty leaf finishes the lanes whose hit lies inside their interval.
    live_ &= ~Simd::bits(Simd::le(active, Simd::load(hit_t_), Simd::load(t_max_)));
    return;
  }
  if (__builtin_popcount(Simd::bits(active)) >= kLeafLanesMin) {
    leaf_lanes(image, n, active, lanes);
    return;
  }
  for (uint32_t m = Simd::bits(active); m != 0; m &= m - 1) {
    const int i = __builtin_ctz(m);
    // leaf_step() up to its pop, with the single-ray code.
    Hit h = hit(i);
    const bool done = detail::leaf_triangles(wray_[i], h, ray_t_max_[i],
                                             (any_hit_ >> i & 1u) != 0, image, n, lanes.lane(i))
                          .done;
    set_hit(i, h);
    // As leaf_step(): finished when the hit lies inside the leaf's interval, or (any-hit) found.
    if (done || h.t <= t_max_[i]) live_ &= ~(1u << i);
  }
}

template <class Simd>
template <class Lanes>
void BasicRayPacket<Simd>::leaf_lanes(const MemoryImage& image, const NodeView& n, Mask active,
                                      Lanes& lanes) {
  const uint8_t* bytes = image.bytes.data();
  // Each lane's list fetch first, as leaf_triangles() reports it.
  if constexpr (!Lanes::kDropsFetches)
    if (n.prim_count >= 2)
      for (uint32_t m = Simd::bits(active); m != 0; m &= m - 1)
        lanes.lane(__builtin_ctz(m)).fetch(Stream::kList, n.list_addr, n.prim_count * 4u);
  // The lanes still testing (an any-hit lane stops at its first hit), and their hits so far.
  __m256 todo = _mm256_castsi256_ps(active.v);
  __m256 ht = _mm256_load_ps(hit_t_), hu = _mm256_load_ps(hit_u_), hv = _mm256_load_ps(hit_v_);
  __m256 htri = _mm256_load_ps(reinterpret_cast<const float*>(hit_tri_));
  const __m256 ray_t_max = _mm256_load_ps(ray_t_max_);
  const __m256 any_hit = _mm256_castsi256_ps(Simd::from_bits(any_hit_).v);
  uint32_t done = 0;  // any-hit lanes that found one
  ++stats_.lane_leaves;
  for (uint32_t k = 0; k < n.prim_count; ++k) {
    const uint32_t tri = detail::leaf_triangle(image, n, k);
    const uint64_t ta = image.triangle_addr(tri);
    if constexpr (!Lanes::kDropsFetches)
      for (uint32_t m = static_cast<uint32_t>(_mm256_movemask_ps(todo)); m != 0; m &= m - 1)
        lanes.lane(__builtin_ctz(m)).fetch(Stream::kTriangle, ta, MemoryImage::kTriangleBytes);
    // record_hit()'s limit std::min(hit.t, ray_t_max): ray_t_max < hit.t ? ray_t_max : hit.t.
    const WatertightLanes8::Outcome o =
        wlanes_.test(bytes + ta, todo, _mm256_min_ps(ray_t_max, ht));
    __m256 got = o.hit;
    ht = _mm256_blendv_ps(ht, o.t, got);
    hu = _mm256_blendv_ps(hu, o.u, got);
    hv = _mm256_blendv_ps(hv, o.v, got);
    htri = _mm256_blendv_ps(htri, _mm256_castsi256_ps(_mm256_set1_epi32(static_cast<int>(tri))),
                            got);
    if (!_mm256_testz_ps(o.scalar, o.scalar)) [[unlikely]] {
      // The single-ray test for these lanes, on the hits so far.
      _mm256_store_ps(hit_t_, ht);
      _mm256_store_ps(hit_u_, hu);
      _mm256_store_ps(hit_v_, hv);
      _mm256_store_ps(reinterpret_cast<float*>(hit_tri_), htri);
      uint32_t scalar_hits = 0;
      const detail::PackedFloats v{bytes + ta};
      for (uint32_t m = static_cast<uint32_t>(_mm256_movemask_ps(o.scalar)); m != 0; m &= m - 1) {
        const int i = __builtin_ctz(m);
        ++stats_.lane_scalar_tests;
        Hit h = hit(i);
        if (detail::record_hit(h, ray_t_max_[i], tri,
                               [&](float t_limit, float& t, float& bu, float& bv) {
                                 return intersect_watertight(wray_[i], v, t_limit, t, bu, bv);
                               })) {
          set_hit(i, h);
          scalar_hits |= 1u << i;
        }
      }
      ht = _mm256_load_ps(hit_t_);
      hu = _mm256_load_ps(hit_u_);
      hv = _mm256_load_ps(hit_v_);
      htri = _mm256_load_ps(reinterpret_cast<const float*>(hit_tri_));
      got = _mm256_or_ps(got, _mm256_castsi256_ps(Simd::from_bits(scalar_hits).v));
    }
    // Any-hit lanes that hit are done here.
    const __m256 finished = _mm256_and_ps(got, any_hit);
    if (!_mm256_testz_ps(finished, finished)) {
      done |= static_cast<uint32_t>(_mm256_movemask_ps(finished));
      todo = _mm256_andnot_ps(finished, todo);
      if (_mm256_testz_ps(todo, todo)) break;
    }
  }
  _mm256_store_ps(hit_t_, ht);
  _mm256_store_ps(hit_u_, hu);
  _mm256_store_ps(hit_v_, hv);
  _mm256_store_ps(reinterpret_cast<float*>(hit_tri_), htri);
  // As leaf_step(): finished when the hit lies inside the leaf's interval, or (any-hit) found.
  live_ &= ~(done | Simd::bits(Simd::le(active, ht, Simd::load(t_max_))));
}

template <class Simd>
template <class Decoder, class Lanes>
[[gnu::flatten]] void BasicRayPacket<Simd>::traverse(const MemoryImage& image, Lanes& lanes) {
  using S = Simd;
  Entry stack[kStackDepth];
  int sp = 0;
  Mask active = S::from_bits(live_);
  if (!S::any(active)) return;
  uint64_t node = image.root_addr;
  Vec t_min = S::load(t_min_), t_max = S::load(t_max_);
  const Vec zero = S::zero(), ulp_margin = S::set1(0x1p-19f);
  for (;;) {
    // Descent: interior nodes until a leaf, each one vector step for the active lanes.
    report_node(image, node, active, lanes);
    NodeView n = Decoder::decode(image, node);
    while (!n.leaf) {
      const int a = n.axis;
      const Vec split = S::set1(n.split);
      const Vec o = S::load(org_[a]);
      // interior_step()'s values, lane by lane: below_first, t_plane, slack.
      const Mask below = S::lt(active, S::load(org_side_[a]), split);
      const Vec t_plane = S::mul(S::sub(split, o), S::load(inv_dir_[a]));
      const Vec slack =
          S::mul(S::mul(S::add(S::abs(split), S::abs(o)), S::load(abs_inv_dir_[a])), ulp_margin);
      const Vec lo = S::sub(t_plane, slack), hi = S::add(t_plane, slack);
      // Its cases: near only (plane behind or beyond), far only (entered past the plane), both.
      const Mask near_only = S::le(active, t_plane, zero) | S::gt(active, lo, t_max);
      const Mask far_only = S::lt(active & ~near_only, hi, t_min);
      const Mask both = active & ~near_only & ~far_only;
      const Mask near_set = active & ~far_only, far_set = active & ~near_only;
      // Intervals: near [t_min, min(t_max, hi)], far [max(t_min, lo), t_max] for `both` lanes;
      // a one-child lane keeps its own.
      const Vec near_max = S::blend(S::lt(both, hi, t_max), t_max, hi);
      const Vec far_min = S::blend(S::lt(both, t_min, lo), t_min, lo);
      // Visits in order: below (below-first lanes' near set), above (below-first lanes' far
      // set, above-first lanes' near set), below again (above-first lanes' far set).
      const Mask above = active & ~below;
      const Mask first = below & near_set;
      const Mask second = (below & far_set) | (above & near_set);
      const Mask third = above & far_set;
      stats_.mixed_splits += S::any(below) && S::any(above);
      if (S::any(third)) [[unlikely]]
        stack[sp++] = {far_min, t_max, n.below_addr, third};
      const Vec second_min = S::blend(below, t_min, far_min);
      const Vec second_max = S::blend(below, near_max, t_max);
      if (S::any(first)) {
        if (S::any(second)) stack[sp++] = {second_min, second_max, n.above_addr, second};
        node = n.below_addr;
        active = first;
        t_max = near_max;
      } else if (S::any(second)) {
        node = n.above_addr;
        active = second;
        t_min = second_min;
        t_max = second_max;
      } else {
        --sp;  // the third set alone: visit it now rather than from the stack
        node = n.below_addr;
        active = third;
        t_min = far_min;
      }
      report_node(image, node, active, lanes);
      n = Decoder::decode(image, node);
    }
    S::store(t_max_, t_max);
    leaf(image, n, active, lanes);
    // Pop: the next entry with a lane still live whose interval can hold a closer hit.
    const Vec hit_t = S::load(hit_t_);
    active = S::from_bits(0);
    while (sp > 0 && !S::any(active)) {
      const Entry& e = stack[--sp];
      // traversal_pop()'s test: a lane skips the entry when e.t_min > hit.t.
      active = S::ngt(e.lanes & S::from_bits(live_), e.t_min, hit_t);
      node = e.addr;
      t_min = e.t_min;
      t_max = e.t_max;
    }
    if (!S::any(active)) return;
  }
}

// The host's packet: 8 lanes wherever AVX2 is there. On AVX-512 hosts too: 16-lane packets
// without the lanes' leaf test ran Kitchen's primary rays at 0.79x Embree against 1.2x for these
// (AMD EPYC Zen 5, Dec 3 2026).
using RayPacket = BasicRayPacket<PacketSimd8>;

}  // namespace rtusim
#endif
