// O(N log N) SAH kd-tree builder after Wald & Havran 2006, "On building fast kd-trees for ray
// tracing, and on doing that in O(N log N)": events of all three axes are generated and sorted
// once; each node sweeps its sorted list, classifies triangles against the chosen plane, clips
// only the straddling ones to the child boxes and merges their few new events back in order.
#include "kdtree/sah_builder.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "kdtree/split_event.h"
#include "kdtree/triangle_clip.h"

namespace rtusim {

using kd_detail::EventType;
using kd_detail::SplitEvent;

int kd_max_depth(uint64_t triangle_count, const KdBuildParams& params) {
  if (params.max_depth >= 0) return params.max_depth;
  if (triangle_count == 0) return 8;
  return std::min(KdBuildParams::kMaxDepthLimit,
                  static_cast<int>(std::lround(8.0 + 1.3 * std::log2(static_cast<double>(triangle_count)))));
}

namespace {

// Which child a triangle goes to once a node's plane is chosen.
enum class Side : uint8_t { kBoth = 0, kBelow = 1, kAbove = 2 };

// The best plane found by a node's sweep; axis -1 when no split beats a leaf.
struct SplitChoice {
  int axis = -1;
  float pos = 0.0f;
  bool planar_below = true;  // triangles lying in the plane go below (else above)
  double cost = std::numeric_limits<double>::infinity();
};

// Stable LSD radix sort of events on bits 28..63 (axis, position, type) in three 12-bit passes.
// Input generated in ascending triangle order therefore ends up in the full total order.
void radix_sort_events(std::vector<SplitEvent>& events, std::vector<SplitEvent>& scratch) {
  constexpr int kBits = 12;
  constexpr size_t kBuckets = size_t(1) << kBits;
  scratch.resize(events.size());
  std::vector<size_t> count(kBuckets);
  for (int pass = 0; pass < 3; ++pass) {
    const int shift = 28 + pass * kBits;
    std::fill(count.begin(), count.end(), 0);
    for (SplitEvent e : events) ++count[(e >> shift) & (kBuckets - 1)];
    size_t sum = 0;
    for (size_t& c : count) sum += std::exchange(c, sum);
    for (SplitEvent e : events) scratch[count[(e >> shift) & (kBuckets - 1)]++] = e;
    events.swap(scratch);
  }
}

// Appends the events of a triangle whose (clipped) bounds in the node are `b`.
void push_events(std::vector<SplitEvent>& out, const Bounds3f& b, uint32_t tri) {
  for (int axis = 0; axis < 3; ++axis) {
    if (b.min[axis] == b.max[axis]) {
      out.push_back(kd_detail::make_event(axis, b.min[axis], EventType::kPlanar, tri));
    } else {
      out.push_back(kd_detail::make_event(axis, b.min[axis], EventType::kStart, tri));
      out.push_back(kd_detail::make_event(axis, b.max[axis], EventType::kEnd, tri));
    }
  }
}

// The [begin, end) run of `axis` in a sorted event list.
std::pair<size_t, size_t> axis_range(const std::vector<SplitEvent>& events, int axis) {
  const auto first = std::lower_bound(events.begin(), events.end(), kd_detail::axis_begin_key(axis));
  const auto last = axis == 2 ? events.end()
                              : std::lower_bound(first, events.end(),
                                                 kd_detail::axis_begin_key(axis + 1));
  return {size_t(first - events.begin()), size_t(last - events.begin())};
}

bool finite_triangle(const std::array<glm::vec3, 3>& v) {
  for (const glm::vec3& p : v)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
  return true;
}

class SahBuilder {
 public:
  SahBuilder(const Scene& scene, const KdBuildParams& params) : scene_(scene), params_(params) {}

  KdTree build();

 private:
  // Builds the subtree of a node from its sorted events (consumed); returns the node index.
  uint32_t build_node(std::vector<SplitEvent>& events, uint32_t tri_count, const Bounds3f& box,
                      int depth);
  // The SAH sweep over all three axes.
  SplitChoice find_split(const std::vector<SplitEvent>& events, uint32_t tri_count,
                         const Bounds3f& box) const;
  // Classifies, clips straddlers and fills the children's sorted lists; `events` is consumed
  // (its buffer becomes `below`).
  void split_events(std::vector<SplitEvent>& events, const SplitChoice& split,
                    const Bounds3f& below_box, const Bounds3f& above_box,
                    std::vector<SplitEvent>& below, std::vector<SplitEvent>& above,
                    uint32_t& below_count, uint32_t& above_count);
  void make_leaf(KdNode& node, const std::vector<SplitEvent>& events);
  void fill_report(KdTree& tree) const;

  // Working-set accounting: bytes of the event lists and scratch arrays alive right now.
  void track(const std::vector<SplitEvent>& v, bool alloc) {
    const uint64_t bytes = v.capacity() * sizeof(SplitEvent);
    live_bytes_ = alloc ? live_bytes_ + bytes : live_bytes_ - bytes;
    peak_bytes_ = std::max(peak_bytes_, live_bytes_);
  }
  void release(std::vector<SplitEvent>& v) {
    track(v, false);
    std::vector<SplitEvent>().swap(v);
  }
  // Grows a reused scratch list to `size` entries, accounting the capacity change.
  void reserve_scratch(std::vector<SplitEvent>& v, size_t size) {
    if (v.capacity() >= size) return;
    track(v, false);
    v.reserve(size);
    track(v, true);
  }

  const Scene& scene_;
  KdBuildParams params_;
  int max_depth_ = 0;
  std::vector<KdNode> nodes_;
  std::vector<uint32_t> refs_;
  std::vector<Side> side_;             // per scene triangle; valid for the node being split
  std::vector<uint32_t> straddlers_;   // triangles of the node being split that go both ways
  std::vector<SplitEvent> new_below_;  // clipped events of the straddlers, per child
  std::vector<SplitEvent> new_above_;
  uint64_t live_bytes_ = 0;
  uint64_t peak_bytes_ = 0;
};

KdTree SahBuilder::build() {
  const auto start = std::chrono::steady_clock::now();
  const uint32_t scene_tris = scene_.triangle_count();
  if (scene_.triangles.size() > kd_detail::kMaxTriangles)
    throw std::length_error("kd-tree builder: at most " + std::to_string(kd_detail::kMaxTriangles) +
                            " triangles, scene has " + std::to_string(scene_.triangles.size()));

  // Initial events from the triangles' own bounds, in triangle order, then one radix sort.
  // Triangles with a non-finite vertex cannot be hit and are left out.
  KdTree tree;
  std::vector<SplitEvent> events;
  events.reserve(size_t(scene_tris) * 6);
  track(events, true);
  uint32_t tri_count = 0;
  for (uint32_t t = 0; t < scene_tris; ++t) {
    const auto v = scene_.vertices(t);
    if (!finite_triangle(v)) continue;
    Bounds3f b;
    for (const glm::vec3& p : v) b.extend(p);
    tree.bounds.extend(b);
    push_events(events, b, t);
    ++tri_count;
  }
  {
    std::vector<SplitEvent> scratch;
    radix_sort_events(events, scratch);
    peak_bytes_ = std::max(peak_bytes_, live_bytes_ + scratch.capacity() * sizeof(SplitEvent));
  }
  if (tri_count == 0) tree.bounds = Bounds3f{glm::vec3(0.0f), glm::vec3(0.0f)};

  max_depth_ = kd_max_depth(tri_count, params_);
  side_.assign(scene_tris, Side::kBoth);
  build_node(events, tri_count, tree.bounds, 0);

  tree.nodes = std::move(nodes_);
  tree.refs = std::move(refs_);
  // Peak: event lists and scratch at their largest, plus the per-triangle side array and the
  // output arrays (which only grow).
  tree.report.peak_build_bytes = peak_bytes_ + side_.capacity() * sizeof(Side) +
                                 straddlers_.capacity() * sizeof(uint32_t) +
                                 tree.nodes.capacity() * sizeof(KdNode) +
                                 tree.refs.capacity() * sizeof(uint32_t);
  fill_report(tree);
  tree.report.build_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return tree;
}

uint32_t SahBuilder::build_node(std::vector<SplitEvent>& events, uint32_t tri_count,
                                const Bounds3f& box, int depth) {
  // New node with all bytes zeroed, padding included, so trees compare and hash byte for byte.
  const uint32_t index = static_cast<uint32_t>(nodes_.size());
  nodes_.emplace_back();
  std::memset(static_cast<void*>(&nodes_.back()), 0, sizeof(KdNode));

  // Leaf when small enough, deep enough, or when no plane beats intersecting everything here.
  SplitChoice split;
  if (tri_count > static_cast<uint32_t>(std::max(params_.leaf_prims, 0)) && depth < max_depth_)
    split = find_split(events, tri_count, box);
  if (split.axis < 0 || !(split.cost < double(params_.isect_cost) * tri_count)) {
    make_leaf(nodes_[index], events);
    release(events);
    return index;
  }

  // Interior node: hand each child its sorted events (ours become below's), recurse below then
  // above.
  Bounds3f below_box = box, above_box = box;
  below_box.max[split.axis] = split.pos;
  above_box.min[split.axis] = split.pos;
  std::vector<SplitEvent> below, above;
  uint32_t below_count = 0, above_count = 0;
  split_events(events, split, below_box, above_box, below, above, below_count, above_count);
  const uint32_t below_index = build_node(below, below_count, below_box, depth + 1);
  const uint32_t above_index = build_node(above, above_count, above_box, depth + 1);

  KdNode& node = nodes_[index];
  node.axis = static_cast<uint8_t>(split.axis);
  node.split = split.pos;
  node.below = below_index;
  node.above = above_index;
  return index;
}

SplitChoice SahBuilder::find_split(const std::vector<SplitEvent>& events, uint32_t tri_count,
                                   const Bounds3f& box) const {
  SplitChoice best;
  const double box_area = box.surface_area();
  if (!(box_area > 0.0)) return best;  // a line or point box: nothing to gain
  const double inv_area = 1.0 / box_area;
  const double traversal = params_.traversal_cost, isect = params_.isect_cost;
  const double empty_bonus = params_.empty_bonus;
  const int64_t n = tri_count;

  // SAH of one candidate: below/above counts with planar triangles already assigned.
  // A plane on a box face leaves one child with the whole box; it is allowed (it cuts off flat
  // cells of planar triangles) only if that child then holds fewer triangles than this node.
  auto consider = [&](int axis, float pos, double area_below, double area_above, int64_t n_below,
                      int64_t n_above, bool planar_below, bool at_min, bool at_max) {
    if ((at_min && n_above >= n) || (at_max && n_below >= n)) return;
    const double bonus = (n_below == 0 || n_above == 0) ? empty_bonus : 0.0;
    const double cost = traversal + isect * (1.0 - bonus) *
                                        (area_below * inv_area * double(n_below) +
                                         area_above * inv_area * double(n_above));
    if (cost < best.cost) best = SplitChoice{axis, pos, planar_below, cost};
  };

  // One sweep per axis over its sorted run; events at one position come as ends, planars, starts.
  const glm::vec3 d = box.diagonal();
  size_t i = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const auto [first, last] = axis_range(events, axis);
    i = first;
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    if (!(d[axis] > 0.0f)) continue;  // flat along this axis: every plane is the box itself
    const double cap = double(d[a1]) * double(d[a2]);
    const double rim = double(d[a1]) + double(d[a2]);
    const float lo = box.min[axis], hi = box.max[axis];
    int64_t n_below = 0, n_planar = 0, n_above = n;
    while (i < last) {
      const uint32_t key = kd_detail::event_position_key(events[i]);
      const float pos = kd_detail::event_position(events[i]);
      int64_t ends = 0, planars = 0, starts = 0;
      while (i < last && kd_detail::event_position_key(events[i]) == key &&
             kd_detail::event_type(events[i]) == EventType::kEnd) ++ends, ++i;
      while (i < last && kd_detail::event_position_key(events[i]) == key &&
             kd_detail::event_type(events[i]) == EventType::kPlanar) ++planars, ++i;
      while (i < last && kd_detail::event_position_key(events[i]) == key &&
             kd_detail::event_type(events[i]) == EventType::kStart) ++starts, ++i;
      n_planar = planars;
      n_above -= planars + ends;
      const double area_below = 2.0 * (cap + (double(pos) - lo) * rim);
      const double area_above = 2.0 * (cap + (double(hi) - pos) * rim);
      const bool at_min = pos <= lo, at_max = pos >= hi;
      // Planar triangles below first, so an exact tie keeps them below (deterministic).
      consider(axis, pos, area_below, area_above, n_below + n_planar, n_above, true, at_min, at_max);
      if (n_planar > 0)
        consider(axis, pos, area_below, area_above, n_below, n_above + n_planar, false, at_min,
                 at_max);
      n_below += starts + planars;
      n_planar = 0;
    }
  }
  return best;
}

void SahBuilder::split_events(std::vector<SplitEvent>& events, const SplitChoice& split,
                              const Bounds3f& below_box, const Bounds3f& above_box,
                              std::vector<SplitEvent>& below, std::vector<SplitEvent>& above,
                              uint32_t& below_count, uint32_t& above_count) {
  // Classify on the split axis: ends at or before the plane go below, starts at or after it go
  // above, planar ones by position (the sweep's choice when exactly on the plane); the rest
  // straddle.
  const auto [first, last] = axis_range(events, split.axis);
  const uint32_t split_key = kd_detail::position_key(split.pos);
  for (size_t i = first; i < last; ++i) side_[kd_detail::event_triangle(events[i])] = Side::kBoth;
  for (size_t i = first; i < last; ++i) {
    const SplitEvent e = events[i];
    const uint32_t key = kd_detail::event_position_key(e);
    const EventType type = kd_detail::event_type(e);
    Side& side = side_[kd_detail::event_triangle(e)];
    if (type == EventType::kEnd && key <= split_key) {
      side = Side::kBelow;
    } else if (type == EventType::kStart && key >= split_key) {
      side = Side::kAbove;
    } else if (type == EventType::kPlanar) {
      side = (key < split_key || (key == split_key && split.planar_below)) ? Side::kBelow
                                                                           : Side::kAbove;
    }
  }

  // Count triangles per side (one start-or-planar event each on this axis), list straddlers.
  uint32_t only_below = 0, only_above = 0;
  straddlers_.clear();
  for (size_t i = first; i < last; ++i) {
    const SplitEvent e = events[i];
    if (kd_detail::event_type(e) == EventType::kEnd) continue;
    const uint32_t tri = kd_detail::event_triangle(e);
    switch (side_[tri]) {
      case Side::kBelow: ++only_below; break;
      case Side::kAbove: ++only_above; break;
      case Side::kBoth: straddlers_.push_back(tri); break;
    }
  }
  const uint32_t straddling = static_cast<uint32_t>(straddlers_.size());
  below_count = only_below + straddling;
  above_count = only_above + straddling;

  // Perfect splits: clip each straddler to both child boxes; if rounding empties a clip, use
  // the triangle's bounds clamped into the child box so the triangle is never lost.
  std::sort(straddlers_.begin(), straddlers_.end());
  new_below_.clear();
  new_above_.clear();
  reserve_scratch(new_below_, size_t(straddling) * 6);
  reserve_scratch(new_above_, size_t(straddling) * 6);
  for (uint32_t tri : straddlers_) {
    const auto v = scene_.vertices(tri);
    Bounds3f tri_bounds;
    for (const glm::vec3& p : v) tri_bounds.extend(p);
    Bounds3f b = clip_triangle_bounds(v, below_box);
    push_events(new_below_, b.empty() ? clamp_bounds_into(tri_bounds, below_box) : b, tri);
    b = clip_triangle_bounds(v, above_box);
    push_events(new_above_, b.empty() ? clamp_bounds_into(tri_bounds, above_box) : b, tri);
  }
  std::sort(new_below_.begin(), new_below_.end());
  std::sort(new_above_.begin(), new_above_.end());

  // Above: the one-sided triangles' events (still sorted) merged with the new sorted ones.
  // Below: compacted to the front of `events` in the same pass, then merged in place from the
  // back, so the parent's list becomes the below child's without another allocation.
  above.reserve(std::min(events.size(), size_t(6) * only_above) + new_above_.size());
  size_t kept_below = 0, na = 0;
  for (SplitEvent e : events) {
    const Side s = side_[kd_detail::event_triangle(e)];
    if (s == Side::kBelow) {
      events[kept_below++] = e;
    } else if (s == Side::kAbove) {
      while (na < new_above_.size() && new_above_[na] < e) above.push_back(new_above_[na++]);
      above.push_back(e);
    }
  }
  above.insert(above.end(), new_above_.begin() + na, new_above_.end());
  track(above, true);

  track(events, false);
  const size_t below_size = kept_below + new_below_.size();
  events.resize(below_size);
  for (size_t i = kept_below, j = new_below_.size(), k = below_size; j > 0;)
    events[--k] = (i > 0 && events[i - 1] > new_below_[j - 1]) ? events[--i] : new_below_[--j];
  if (events.capacity() > 2 * below_size + 1024) events.shrink_to_fit();
  below = std::move(events);
  std::vector<SplitEvent>().swap(events);
  track(below, true);
}

void SahBuilder::make_leaf(KdNode& node, const std::vector<SplitEvent>& events) {
  // Each triangle has exactly one start or planar event on axis 0.
  node.axis = KdNode::kLeaf;
  node.first_ref = static_cast<uint32_t>(refs_.size());
  const auto [first, last] = axis_range(events, 0);
  for (size_t i = first; i < last; ++i)
    if (kd_detail::event_type(events[i]) != EventType::kEnd)
      refs_.push_back(kd_detail::event_triangle(events[i]));
  std::sort(refs_.begin() + node.first_ref, refs_.end());
  node.ref_count = static_cast<uint32_t>(refs_.size()) - node.first_ref;
}

void SahBuilder::fill_report(KdTree& tree) const {
  // Walk the tree with node boxes for counts, depths and the SAH cost.
  KdTreeReport& r = tree.report;
  const double root_area = tree.bounds.surface_area();
  struct Item {
    uint32_t node;
    Bounds3f box;
    uint32_t depth;
  };
  std::vector<Item> stack{{0, tree.bounds, 0}};
  uint64_t leaf_depth_sum = 0, filled_leaves = 0;
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    const KdNode& node = tree.nodes[item.node];
    const double area_ratio = root_area > 0.0 ? item.box.surface_area() / root_area : 1.0;
    ++r.nodes;
    r.max_depth = std::max(r.max_depth, item.depth);
    if (node.is_leaf()) {
      ++r.leaves;
      if (node.ref_count == 0) {
        ++r.empty_leaves;
      } else {
        ++filled_leaves;
        leaf_depth_sum += item.depth;
      }
      r.sah_cost += double(params_.isect_cost) * node.ref_count * area_ratio;
    } else {
      r.sah_cost += double(params_.traversal_cost) * area_ratio;
      stack.push_back({node.above, KdTree::above_bounds(node, item.box), item.depth + 1});
      stack.push_back({node.below, KdTree::below_bounds(node, item.box), item.depth + 1});
    }
  }
  r.mean_leaf_depth = filled_leaves ? double(leaf_depth_sum) / double(filled_leaves) : 0.0;
  const uint32_t tris = scene_.triangle_count();
  r.refs_per_triangle = tris ? double(tree.refs.size()) / double(tris) : 0.0;
}

}  // namespace

KdTree build_sah_kd_tree(const Scene& scene, const KdBuildParams& params) {
  SahBuilder builder(scene, params);
  return builder.build();
}

}  // namespace rtusim
