// Up to 16 rays traversing the kd-tree together (AVX-512): one node fetch and decode, and one
// vector step, serve every ray that visits the node. Each ray's result is the single-ray one:
// its hit bit for bit, and its own fetches (node, list, triangle) in the order traverse()
// reports them for that ray alone.
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
// single-ray leaf code. Lanes the packet does not take (admits() false) go through traverse().
#pragma once
#if defined(__AVX512F__)
#include <immintrin.h>

#include <cstdint>

#include "traversal/traversal.h"

namespace rtusim {

class RayPacket {
 public:
  static constexpr int kLanes = 16;

  // What a packet traversal did (for tests).
  struct Stats {
    uint64_t mixed_splits = 0;  // interior steps whose lanes disagreed on the near side
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
    ray_t_max_[lane] = ray.t_max;
    t_min_[lane] = s.t_min;
    t_max_[lane] = s.t_max;
    hits_[lane] = s.hit;
    hit_t_[lane] = s.hit.t;
    const uint32_t bit = 1u << lane;
    any_hit_ = any_hit ? any_hit_ | bit : any_hit_ & ~bit;
    live_ = s.done ? live_ & ~bit : live_ | bit;
  }

  const Hit& hit(int lane) const { return hits_[lane]; }
  const Stats& stats() const { return stats_; }

  // Traverses the live lanes to the end. `lanes.lane(i)` is lane i's fetch sink (the single-ray
  // sink interface), and `Lanes::kDropsFetches` says that all of them drop every fetch;
  // `Decoder` is the layout's static decode(image, addr) -> NodeView.
  template <class Decoder, class Lanes>
  void traverse(const MemoryImage& image, Lanes& lanes);

 private:
  // Entries: at most two per interior node on the path to the node being visited.
  static constexpr int kStackDepth = 2 * TraversalState::kStackDepth;
  struct Entry {
    __m512 t_min, t_max;  // per lane: the interval in the child
    uint64_t addr;        // the child
    __mmask16 lanes;      // the lanes that visit it
  };

  // Reports the node fetch of every lane in `active`.
  template <class Lanes>
  static void report_node(const MemoryImage& image, uint64_t node, __mmask16 active,
                          Lanes& lanes) {
    if constexpr (!Lanes::kDropsFetches)
      for (uint32_t m = active; m != 0; m &= m - 1)
        lanes.lane(__builtin_ctz(m)).fetch(Stream::kNode, node, image.node_bytes);
  }

  // Tests a leaf's triangles for every lane in `active` (their intervals end at t_max_); lanes
  // that finish here leave the live mask.
  template <class Lanes>
  void leaf(const MemoryImage& image, const NodeView& n, __mmask16 active, Lanes& lanes);

  alignas(64) float org_[3][kLanes], inv_dir_[3][kLanes], abs_inv_dir_[3][kLanes];
  alignas(64) float org_side_[3][kLanes];  // TraversalState::org_side
  alignas(64) float t_min_[kLanes], t_max_[kLanes];  // at set_lane(); the leaf's interval
  alignas(64) float hit_t_[kLanes];                  // hits_[i].t
  float ray_t_max_[kLanes];
  Hit hits_[kLanes];
  WatertightRay wray_[kLanes];
  uint32_t any_hit_ = 0;  // lanes in any-hit mode
  uint32_t live_ = 0;     // lanes not finished
  Stats stats_;
};

template <class Lanes>
void RayPacket::leaf(const MemoryImage& image, const NodeView& n, __mmask16 active,
                     Lanes& lanes) {
  if (n.prim_count == 0) {
    // An empty leaf finishes the lanes whose hit lies inside their interval.
    live_ &= ~static_cast<uint32_t>(_mm512_mask_cmp_ps_mask(
        active, _mm512_load_ps(hit_t_), _mm512_load_ps(t_max_), _CMP_LE_OQ));
    return;
  }
  for (uint32_t m = active; m != 0; m &= m - 1) {
    const int i = __builtin_ctz(m);
    // leaf_step() up to its pop, with the single-ray code.
    const bool done = detail::leaf_triangles(wray_[i], hits_[i], ray_t_max_[i],
                                             (any_hit_ >> i & 1u) != 0, image, n, lanes.lane(i))
                          .done;
    hit_t_[i] = hits_[i].t;
    // As leaf_step(): finished when the hit lies inside the leaf's interval, or (any-hit) found.
    if (done || hits_[i].t <= t_max_[i]) live_ &= ~(1u << i);
  }
}

template <class Decoder, class Lanes>
[[gnu::flatten]] void RayPacket::traverse(const MemoryImage& image, Lanes& lanes) {
  Entry stack[kStackDepth];
  int sp = 0;
  __mmask16 active = static_cast<__mmask16>(live_);
  if (active == 0) return;
  uint64_t node = image.root_addr;
  __m512 t_min = _mm512_load_ps(t_min_), t_max = _mm512_load_ps(t_max_);
  const __m512 zero = _mm512_setzero_ps(), ulp_margin = _mm512_set1_ps(0x1p-19f);
  for (;;) {
    // Descent: interior nodes until a leaf, each one vector step for the active lanes.
    report_node(image, node, active, lanes);
    NodeView n = Decoder::decode(image, node);
    while (!n.leaf) {
      const int a = n.axis;
      const __m512 split = _mm512_set1_ps(n.split);
      const __m512 o = _mm512_load_ps(org_[a]);
      // interior_step()'s values, lane by lane: below_first, t_plane, slack.
      const __mmask16 below =
          _mm512_mask_cmp_ps_mask(active, _mm512_load_ps(org_side_[a]), split, _CMP_LT_OQ);
      const __m512 t_plane = _mm512_mul_ps(_mm512_sub_ps(split, o), _mm512_load_ps(inv_dir_[a]));
      const __m512 slack = _mm512_mul_ps(
          _mm512_mul_ps(_mm512_add_ps(_mm512_abs_ps(split), _mm512_abs_ps(o)),
                        _mm512_load_ps(abs_inv_dir_[a])),
          ulp_margin);
      const __m512 lo = _mm512_sub_ps(t_plane, slack), hi = _mm512_add_ps(t_plane, slack);
      // Its cases: near only (plane behind or beyond), far only (entered past the plane), both.
      const __mmask16 near_only =
          _mm512_mask_cmp_ps_mask(active, t_plane, zero, _CMP_LE_OQ) |
          _mm512_mask_cmp_ps_mask(active, lo, t_max, _CMP_GT_OQ);
      const __mmask16 far_only =
          _mm512_mask_cmp_ps_mask(active & ~near_only, hi, t_min, _CMP_LT_OQ);
      const __mmask16 both = active & ~near_only & ~far_only;
      const __mmask16 near_set = active & ~far_only, far_set = active & ~near_only;
      // Intervals: near [t_min, min(t_max, hi)], far [max(t_min, lo), t_max] for `both` lanes;
      // a one-child lane keeps its own.
      const __m512 near_max = _mm512_mask_blend_ps(
          _mm512_mask_cmp_ps_mask(both, hi, t_max, _CMP_LT_OQ), t_max, hi);
      const __m512 far_min = _mm512_mask_blend_ps(
          _mm512_mask_cmp_ps_mask(both, t_min, lo, _CMP_LT_OQ), t_min, lo);
      // Visits in order: below (below-first lanes' near set), above (below-first lanes' far
      // set, above-first lanes' near set), below again (above-first lanes' far set).
      const __mmask16 above = active & ~below;
      const __mmask16 first = below & near_set;
      const __mmask16 second = (below & far_set) | (above & near_set);
      const __mmask16 third = above & far_set;
      stats_.mixed_splits += (below != 0) & (above != 0);
      if (third != 0) [[unlikely]]
        stack[sp++] = {far_min, t_max, n.below_addr, third};
      const __m512 second_min = _mm512_mask_blend_ps(below, t_min, far_min);
      const __m512 second_max = _mm512_mask_blend_ps(below, near_max, t_max);
      if (first != 0) {
        if (second != 0) stack[sp++] = {second_min, second_max, n.above_addr, second};
        node = n.below_addr;
        active = first;
        t_max = near_max;
      } else if (second != 0) {
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
    _mm512_store_ps(t_max_, t_max);
    leaf(image, n, active, lanes);
    // Pop: the next entry with a lane still live whose interval can hold a closer hit.
    const __m512 hit_t = _mm512_load_ps(hit_t_);
    active = 0;
    while (sp > 0 && active == 0) {
      const Entry& e = stack[--sp];
      // traversal_pop()'s test: a lane skips the entry when e.t_min > hit.t.
      active = _mm512_mask_cmp_ps_mask(e.lanes & static_cast<__mmask16>(live_), e.t_min, hit_t,
                                       _CMP_NGT_UQ);
      node = e.addr;
      t_min = e.t_min;
      t_max = e.t_max;
    }
    if (active == 0) return;
  }
}

}  // namespace rtusim
#endif
