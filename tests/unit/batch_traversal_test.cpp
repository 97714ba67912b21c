// Batch (packet) traversal against traverse() ray by ray: on every layout, every ray's hit bit
// for bit and its own fetch sequence (stream, address, size) in order, for coherent camera rays,
// rays from scattered origins (lanes that disagree on a node's near side), rays with zero
// direction components, rays that miss the scene, closest-hit and any-hit mixed. With the host's
// packets (8 lanes with AVX2, AVX-512 hosts included; none otherwise). Then the 8-lane packets'
// leaf test (a triangle against the lanes at once) on a tree of large leaves, with rays whose
// exact arithmetic meets its single-ray cases.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "kdtree/sah_builder.h"
#include "layout/layout.h"
#include "layout/layout_dispatch.h"
#include "scene/builtin_scene.h"
#include "scene/pinhole_camera.h"
#include "test_geometry.h"
#include "traversal/batch_traversal.h"
#include "traversal/fetch_recorder.h"
#include "tracer/fetch_log.h"

namespace rtusim {
namespace {

struct Record {
  Ray ray;
  bool shadow = false;
  bool any_hit() const { return shadow; }
};

// Each ray's fetches, split at end_ray().
struct PerRaySink {
  std::vector<std::vector<RecordedFetch>> rays{1};
  std::vector<size_t> ended;
  void fetch(Stream s, uint64_t addr, uint32_t bytes) { rays.back().push_back({s, addr, bytes}); }
  void end_ray(size_t i) {
    ended.push_back(i);
    rays.emplace_back();
  }
};

// Fetch counts and bytes: the order-free kind of sink.
struct CountSink {
  static constexpr bool kFetchOrderFree = true;
  uint64_t fetches = 0, bytes = 0, addr_sum = 0;
  void fetch(Stream, uint64_t addr, uint32_t n) {
    ++fetches;
    bytes += n;
    addr_sum += addr;
  }
};

bool same_bits(const Hit& a, const Hit& b) {
  return std::memcmp(&a.t, &b.t, 4) == 0 && a.triangle == b.triangle &&
         std::memcmp(&a.u, &b.u, 4) == 0 && std::memcmp(&a.v, &b.v, 4) == 0;
}

struct Scenario {
  std::string name;
  std::vector<Record> rays;
};

// The scenarios on a scene with bounds [lo, hi] and camera `cam`.
std::vector<Scenario> scenarios(const Scene& scene, const MemoryImage& image, uint32_t seed) {
  const glm::vec3 lo(image.bounds_min[0], image.bounds_min[1], image.bounds_min[2]);
  const glm::vec3 hi(image.bounds_max[0], image.bounds_max[1], image.bounds_max[2]);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f), u11(-1.0f, 1.0f);
  auto inside = [&] { return lo + (hi - lo) * glm::vec3(u01(rng), u01(rng), u01(rng)); };
  auto direction = [&] { return glm::vec3(u11(rng), u11(rng), u11(rng)); };
  std::vector<Scenario> out;

  // Camera rays in scan order (16x1 strips), closest hit; then the same as any-hit rays.
  Scenario camera{"camera", {}};
  const PinholeCamera cam(scene.cameras.front(), 48, 32);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 48; ++x) camera.rays.push_back({cam.generate(x, y), false});
  out.push_back(camera);
  Scenario shadow{"camera any-hit, limited", camera.rays};
  for (size_t i = 0; i < shadow.rays.size(); ++i) {
    shadow.rays[i].shadow = true;
    shadow.rays[i].ray.t_max = 0.5f + 3.0f * u01(rng);
  }
  out.push_back(shadow);

  // One origin inside the scene, random directions, closest- and any-hit mixed.
  Scenario common{"common origin", {}};
  const glm::vec3 o = inside();
  for (int i = 0; i < 640; ++i) common.rays.push_back({{o, direction()}, i % 3 == 1});
  out.push_back(common);

  // Scattered origins: lanes disagree on near sides.
  Scenario scattered{"scattered origins", {}};
  for (int i = 0; i < 640; ++i) scattered.rays.push_back({{inside(), direction()}, i % 4 == 3});
  out.push_back(scattered);

  // Scattered origins heading one way (disagreeing on near sides, agreeing on direction), some
  // starting on split planes.
  Scenario parallel{"scattered origins, one direction", {}};
  const glm::vec3 d = direction();
  for (int i = 0; i < 640; ++i) {
    Ray r{inside(), d};
    if (i % 5 == 0) r.origin[i % 3] = lo[i % 3] + 0.5f * (hi[i % 3] - lo[i % 3]);
    parallel.rays.push_back({r, i % 2 == 1});
  }
  out.push_back(parallel);

  // Zero direction components and origins on the bounds, mixed with ordinary rays.
  Scenario zeros{"zero direction components", {}};
  for (int i = 0; i < 640; ++i) {
    glm::vec3 dz = direction();
    if (i % 3 == 0) dz[i % 3 == 0 ? (i / 3) % 3 : 0] = 0.0f;
    if (i % 7 == 0) dz = glm::vec3(0.0f, 0.0f, 0.0f) + glm::vec3(0, 0, i % 2 ? 1.0f : -1.0f);
    if (i % 11 == 0) dz.x = 1e-40f;  // a finite direction whose reciprocal is not
    zeros.rays.push_back({{inside(), dz}, i % 3 == 2});
  }
  out.push_back(zeros);

  // Rays that miss the scene's bounds or start outside them heading away, mixed with hits.
  Scenario misses{"misses", {}};
  const glm::vec3 size = hi - lo;
  for (int i = 0; i < 640; ++i) {
    const glm::vec3 outside = hi + size * (0.5f + u01(rng));
    Ray r = i % 4 == 0 ? Ray{inside(), direction()} : Ray{outside, glm::abs(direction()) + 0.01f};
    if (i % 8 == 1) r.dir = -r.dir;  // towards the scene from outside
    misses.rays.push_back({r, i % 5 == 0});
  }
  out.push_back(misses);
  return out;
}

// A packet type's lanes (1: no packets).
template <class P>
constexpr int lanes_of() {
  if constexpr (std::is_void_v<P>) return 1;
  else return P::kLanes;
}

bool same_fetches(const std::vector<RecordedFetch>& a, const std::vector<RecordedFetch>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].stream != b[i].stream || a[i].addr != b[i].addr || a[i].bytes != b[i].bytes)
      return false;
  return true;
}

// Traces `rays` with traverse_batch_with<D, P>() and ray by ray on `image`, whole and in
// odd-sized parts; expects the same hits and per-ray fetch sequences.
template <class D, class P>
void check(const MemoryImage& image, std::span<const Record> rays, const std::string& what) {
  SCOPED_TRACE(what + " (" + std::to_string(rays.size()) + " rays)");
  std::vector<Hit> want(rays.size());
  std::vector<std::vector<RecordedFetch>> want_fetches(rays.size());
  CountSink want_counts;
  for (size_t i = 0; i < rays.size(); ++i) {
    struct One {
      std::vector<RecordedFetch>& out;
      void fetch(Stream s, uint64_t addr, uint32_t bytes) { out.push_back({s, addr, bytes}); }
    } one{want_fetches[i]};
    want[i] = traverse<D>(image, rays[i].ray, rays[i].any_hit(), one);
    traverse<D>(image, rays[i].ray, rays[i].any_hit(), want_counts);
  }

  // A sink that keeps the order: every ray's own fetches, then its end, in batch order.
  std::vector<Hit> got(rays.size());
  PerRaySink sink;
  traverse_batch_with<D, P>(image, rays, std::span<Hit>(got), sink);
  ASSERT_EQ(sink.ended.size(), rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(sink.ended[i], i);
    ASSERT_TRUE(same_bits(got[i], want[i])) << "ray " << i << " t " << got[i].t << " want "
                                            << want[i].t;
    ASSERT_EQ(sink.rays[i].size(), want_fetches[i].size()) << "ray " << i;
    ASSERT_TRUE(same_fetches(sink.rays[i], want_fetches[i])) << "ray " << i;
  }
  EXPECT_TRUE(sink.rays.back().empty());

  // Dropping the fetches, and counting them (order-free): the same hits and totals.
  std::vector<Hit> dropped(rays.size());
  NullFetchSink none;
  traverse_batch_with<D, P>(image, rays, std::span<Hit>(dropped), none);
  CountSink counts;
  std::vector<Hit> counted(rays.size());
  traverse_batch_with<D, P>(image, rays, std::span<Hit>(counted), counts);
  for (size_t i = 0; i < rays.size(); ++i) {
    ASSERT_TRUE(same_bits(dropped[i], want[i])) << "ray " << i;
    ASSERT_TRUE(same_bits(counted[i], want[i])) << "ray " << i;
  }
  EXPECT_EQ(counts.fetches, want_counts.fetches);
  EXPECT_EQ(counts.bytes, want_counts.bytes);
  EXPECT_EQ(counts.addr_sum, want_counts.addr_sum);
}

// A fetch log's replay: every fetch and ray end, in order.
struct ReplayList {
  std::vector<uint64_t> items;
  void fetch(Stream s, uint64_t addr, uint32_t bytes) {
    items.insert(items.end(), {uint64_t{static_cast<uint8_t>(s)}, addr, bytes});
  }
  void end_ray(uint32_t pixel, RayKind kind, uint64_t /*direct_dram_bytes*/) {
    items.insert(items.end(), {~uint64_t{0}, pixel, static_cast<uint64_t>(kind)});
  }
};

// Records `rays` into a FetchLog ray by ray and batched: the same replay and the same encoding.
template <class D, class P>
void check_log(const MemoryImage& image, std::span<const Record> rays, const std::string& what) {
  SCOPED_TRACE(what + " log");
  std::vector<RayRecord> records(rays.size());
  for (size_t i = 0; i < rays.size(); ++i)
    records[i] = {rays[i].ray, rays[i].shadow ? RayKind::kShadow : RayKind::kPrimary,
                  static_cast<uint32_t>(i)};
  FetchLog want, got;
  want.fetch(Stream::kTriangle, 12345, 36);  // a log that already holds a ray
  got.fetch(Stream::kTriangle, 12345, 36);
  want.end_ray(records.front());
  got.end_ray(records.front());
  for (const RayRecord& r : records) {
    traverse<D>(image, r.ray, r.any_hit(), want);
    want.end_ray(r);
  }
  struct Sink {
    FetchLog& log;
    std::span<const RayRecord> rays;
    void fetch(Stream s, uint64_t addr, uint32_t bytes) { log.fetch(s, addr, bytes); }
    void end_ray(size_t i) { log.end_ray(rays[i]); }
  } sink{got, records};
  std::vector<Hit> hits(records.size());
  traverse_batch_with<D, P>(image, std::span<const RayRecord>(records), std::span<Hit>(hits),
                            sink);
  ReplayList a, b;
  want.replay(a);
  got.replay(b);
  EXPECT_TRUE(a.items == b.items);
  EXPECT_EQ(want.size_bytes(), got.size_bytes());
}

// Traverses `rays` in packets of type P (fetches dropped) and sums `count(packet stats)`.
template <class D, class P, class Count>
uint64_t sum_packet_stats(const MemoryImage& image, const std::vector<Record>& rays, Count count) {
  uint64_t sum = 0;
  batch_detail::DroppingLanes lanes;
  for (size_t b = 0; b < rays.size(); b += P::kLanes) {
    P p;
    p.clear();
    for (size_t i = b; i < std::min(rays.size(), b + P::kLanes); ++i)
      if (P::admits(rays[i].ray))
        p.set_lane(static_cast<int>(i - b), image, rays[i].ray, rays[i].any_hit());
    p.template traverse<D>(image, lanes);
    sum += count(p.stats());
  }
  return sum;
}

// Interior steps, over the packets (type P) of `rays`, whose lanes disagreed on the near side.
template <class D, class P>
uint64_t mixed_splits(const MemoryImage& image, const std::vector<Record>& rays) {
  return sum_packet_stats<D, P>(image, rays,
                                [](const typename P::Stats& st) { return st.mixed_splits; });
}

// Every scenario on `image` with packets of type P (void: ray by ray).
template <class D, class P>
void check_scenarios(const Scene& scene, const MemoryImage& image, const std::string& kind,
                     uint32_t seed) {
  for (const Scenario& sc : scenarios(scene, image, seed)) {
    const std::string what = scene.source + " " + kind + " " + sc.name + " (" +
                             std::to_string(lanes_of<P>()) + " lanes)";
    const std::span<const Record> all(sc.rays);
    check<D, P>(image, all, what);
    check<D, P>(image, all.subspan(5, 37), what);  // groups across the packet boundaries
    check<D, P>(image, all.subspan(3, 1), what);
    check<D, P>(image, all.subspan(0, 17), what);
    check_log<D, P>(image, all, what);
    if constexpr (!std::is_void_v<P>) {
      // The disagreeing-lanes path is taken where origins scatter (and only there).
      if (sc.name.rfind("scattered", 0) == 0) {
        EXPECT_GT((mixed_splits<D, P>(image, sc.rays)), 0u) << what;
      }
      if (sc.name == "common origin") {
        EXPECT_EQ((mixed_splits<D, P>(image, sc.rays)), 0u) << what;
      }
    }
  }
}

void check_scene(const Scene& scene, uint32_t seed) {
  const KdTree tree = build_sah_kd_tree(scene, KdBuildParams{});
  for (const std::string& kind : layout_kinds()) {
    const MemoryImage image = make_layout(kind)->build_image(tree, scene);
    with_layout_decoder(image, [&]<class D>() {
      check_scenarios<D, HostRayPacket>(scene, image, kind, seed);
    });
  }
}

TEST(BatchTraversal, MatchesSingleRayOnBuiltinScene) {
  check_scene(make_builtin_scene("cornell"), 1);
}

TEST(BatchTraversal, MatchesSingleRayOnRandomSoup) {
  Scene scene = testing::random_soup(5, 3000);
  scene.source = "soup";
  CameraDesc cam;
  cam.eye = {0.3f, 0.4f, 3.5f};
  cam.target = {0.0f, 0.0f, 0.0f};
  scene.cameras.push_back(cam);
  check_scene(scene, 2);
}

#if defined(__AVX2__)
TEST(BatchTraversal, PacketLeafTestMatchesSingleRayOnLargeLeaves) {
  // A closed grid box (shared edges) around a soup, in a shallow tree: leaves of 100+ triangles.
  Scene scene = testing::random_soup(7, 1500);
  testing::add_grid_box(scene, {-1.5f, -1.5f, -1.5f}, {1.5f, 1.5f, 1.5f}, 6);
  scene.source = "soup in a box, large leaves";
  CameraDesc cam;
  cam.eye = {0.3f, 0.4f, 1.2f};
  cam.target = {0.0f, 0.0f, 0.0f};
  scene.cameras.push_back(cam);
  KdBuildParams params;
  params.max_depth = 4;
  const KdTree tree = build_sah_kd_tree(scene, params);
  // Exact arithmetic: origins on a 1/8 grid (some on the box's faces), small integer directions
  // (none zero); closest- and any-hit mixed, some limited, some lanes left out of the packet.
  std::mt19937 rng(3);
  auto coarse = [&](int range) {
    return static_cast<float>(static_cast<int>(rng() % (2 * range + 1)) - range) / 8.0f;
  };
  std::vector<Record> exact;
  for (int i = 0; i < 1200; ++i) {
    Ray r;
    for (int a = 0; a < 3; ++a) {
      r.origin[a] = coarse(12);
      const int d = static_cast<int>(rng() % 4) + 1;
      r.dir[a] = static_cast<float>(rng() % 2 ? d : -d);
    }
    if (i % 5 == 0) r.origin[i % 3] = i % 2 ? 1.5f : -1.5f;  // on a face of the box
    if (i % 7 == 0) r.dir[i % 3] = 0.0f;                       // not a lane: ray by ray
    if (i % 4 == 1) r.t_max = 0.25f + static_cast<float>(rng() % 16) / 8.0f;
    exact.push_back({r, i % 3 == 1});
  }
  for (const std::string& kind : {std::string("dfl"), std::string("veb")}) {
    const MemoryImage image = make_layout(kind)->build_image(tree, scene);
    with_layout_decoder(image, [&]<class D>() {
      using P = BasicRayPacket<PacketSimd8>;
      check_scenarios<D, P>(scene, image, kind, 4);
      const std::span<const Record> all(exact);
      check<D, P>(image, all, kind + " exact");
      check<D, P>(image, all.subspan(3, 29), kind + " exact");
      check_log<D, P>(image, all, kind + " exact");
      // The lane test ran, and handed some lanes to the single-ray code.
      EXPECT_GT((sum_packet_stats<D, P>(image, exact,
                                        [](const P::Stats& st) { return st.lane_leaves; })),
                100u)
          << kind;
      EXPECT_GT((sum_packet_stats<D, P>(image, exact,
                                        [](const P::Stats& st) { return st.lane_scalar_tests; })),
                50u)
          << kind;
    });
  }
}
#endif

}  // namespace
}  // namespace rtusim
