// Runs the frame through the configured tier for each layout and gathers the stats.
#include "app/simulation.h"

#include <chrono>
#include <cstring>
#include <filesystem>
#include <optional>
#include <stdexcept>

#include <oneapi/tbb/parallel_for.h>

#include "chip/ray_dealer.h"
#include "sample/sampled_frame.h"
#include "tier/progress_backend.h"
#include "tier/tier.h"
#include "tracer/parallel_render.h"
#include "util/child_processes.h"
#include "util/stat_decl.h"

namespace rtusim {
namespace {
// Stats keys of the run: scene, tree, rays, the layout's image and the report figures.
const StatDecl kSceneTriangles("scene.triangles", StatKind::kProperty, "triangles",
                               "triangles of the scene");
const StatDecl kSceneMaterials("scene.materials", StatKind::kProperty, "materials",
                               "materials of the scene");
const StatDecl kSceneLights("scene.lights", StatKind::kProperty, "lights",
                            "lights of the scene");
const StatDecl kSceneBytes("scene.bytes", StatKind::kProperty, "bytes",
                           "bytes of the scene's geometry as loaded");
const StatDecl kSceneLoadSeconds("scene.load_seconds", StatKind::kTiming, "s",
                                 "wall time to load the scene");
const StatDecl kTreeNodes("tree.nodes", StatKind::kProperty, "nodes",
                          "kd-tree nodes");
const StatDecl kTreeLeaves("tree.leaves", StatKind::kProperty, "nodes",
                           "kd-tree leaves");
const StatDecl kTreeEmptyLeaves("tree.empty_leaves", StatKind::kProperty, "nodes",
                                "leaves without a triangle");
const StatDecl kTreeMaxDepth("tree.max_depth", StatKind::kProperty, "levels",
                             "deepest leaf");
const StatDecl kTreeMeanLeafDepth("tree.mean_leaf_depth", StatKind::kProperty, "levels",
                                  "mean depth of a leaf");
const StatDecl kTreeRefs("tree.refs_per_triangle", StatKind::kProperty, "",
                         "triangle references per triangle");
const StatDecl kTreeSah("tree.sah_cost", StatKind::kProperty, "",
                        "SAH cost of the tree");
const StatDecl kTreeBuildSeconds("tree.build_seconds", StatKind::kTiming, "s",
                                 "wall time to build the tree");
const StatDecl kTreePeakBytes("tree.build_peak_bytes", StatKind::kProperty, "bytes",
                              "peak memory of the build");
const StatDecl kTreeBytes("tree.bytes", StatKind::kProperty, "bytes",
                          "bytes of the layout's nodes (mem.nodes.bytes)");
const StatDecl kRaysTotal("rays.total", StatKind::kCounter, "rays",
                          "rays traced");
const StatDecl kRaysPrimary("rays.primary", StatKind::kCounter, "rays",
                            "primary rays");
const StatDecl kRaysShadow("rays.shadow", StatKind::kCounter, "rays",
                           "shadow rays");
const StatDecl kRaysReflection("rays.reflection", StatKind::kCounter, "rays",
                               "mirror reflection rays");
const StatDecl kRaysRefraction("rays.refraction", StatKind::kCounter, "rays",
                               "refraction rays");
const StatDecl kSimTier("sim.tier", StatKind::kProperty, "",
                        "the fidelity tier");
const StatDecl kFramesPerSecond("report.frames_per_second", StatKind::kProperty, "frames/s",
                                "frame rate of the GB/s figures");
const StatDecl kLayoutKind("layout.kind", StatKind::kProperty, "",
                           "the layout");
const StatDecl kRegionBytes("mem.<stream>.bytes", StatKind::kProperty, "bytes",
                            "bytes of the memory image's region");
const StatDecl kImageBytes("mem.image.bytes", StatKind::kProperty, "bytes",
                           "bytes of the whole memory image");
const StatDecl kL1MissRate("l1.miss_rate", StatKind::kRatio, "",
                           "l1.misses / l1.accesses");
const StatDecl kNodeBytesPerRay("report.node_dram_bytes_per_ray", StatKind::kRatio, "bytes/ray",
                                "dram.bytes.nodes / rays.total");
const StatDecl kDramBytesPerFrame("report.dram_bytes_per_frame", StatKind::kRatio, "bytes/frame",
                                  "DRAM bytes per frame (dram.bytes.total)");
const StatDecl kNodeGbps("report.node_gbytes_per_second", StatKind::kRatio, "GB/s",
                         "node DRAM bytes at report.frames_per_second");
const StatDecl kDramGbpsReport("report.dram_gbytes_per_second", StatKind::kRatio, "GB/s",
                               "DRAM bytes at report.frames_per_second");
const StatDecl kTraceSeconds("trace.seconds", StatKind::kTiming, "s",
                             "wall time to trace the frame through the tier");
const StatDecl kTraceRaysPerSecond("trace.rays_per_second", StatKind::kTiming, "rays/s",
                                   "rays per second of wall time");
}  // namespace


void add_run_stats(const Prepared& p, const FrameResult& frame, Stats& s) {
  const KdTreeReport& r = p.tree.report;
  s.set("scene.triangles", p.scene.triangle_count());
  s.set("scene.materials", p.scene.materials.size());
  s.set("scene.lights", p.scene.lights.size());
  s.set("scene.bytes", p.scene.geometry_bytes());
  s.set("scene.load_seconds", p.scene_load_seconds);
  s.set("tree.nodes", r.nodes);
  s.set("tree.leaves", r.leaves);
  s.set("tree.empty_leaves", r.empty_leaves);
  s.set("tree.max_depth", r.max_depth);
  s.set("tree.mean_leaf_depth", r.mean_leaf_depth);
  s.set("tree.refs_per_triangle", r.refs_per_triangle);
  s.set("tree.sah_cost", r.sah_cost);
  s.set("tree.build_seconds", r.build_seconds);
  s.set("tree.build_peak_bytes", r.peak_build_bytes);
  s.set("rays.total", frame.rays_total());
  s.set("rays.primary", frame.rays_by_kind[int(RayKind::kPrimary)]);
  s.set("rays.shadow", frame.rays_by_kind[int(RayKind::kShadow)]);
  s.set("rays.reflection", frame.rays_by_kind[int(RayKind::kReflection)]);
  s.set("rays.refraction", frame.rays_by_kind[int(RayKind::kRefraction)]);
  s.set("sim.tier", p.config.sim.tier);
  s.set("report.frames_per_second", p.config.report.frames_per_second);
}

void add_image_stats(const MemoryImage& image, Stats& s) {
  s.set("layout.kind", image.layout);
  s.set("tree.bytes", image.nodes.size_bytes);
  s.set("mem.nodes.bytes", image.nodes.size_bytes);
  s.set("mem.lists.bytes", image.lists.size_bytes);
  s.set("mem.triangles.bytes", image.triangles.size_bytes);
  s.set("mem.image.bytes", image.bytes.size());
}

void add_report_stats(const FrameResult& frame, double fps, double seconds, Stats& s) {
  const double rays = static_cast<double>(std::max<uint64_t>(1, frame.rays_total()));
  const double node_bytes = s.at("dram.bytes.nodes").get<double>();
  const double total_bytes = s.at("dram.bytes.total").get<double>();
  const double accesses = s.at("l1.accesses").get<double>();
  s.set("l1.miss_rate", accesses > 0 ? s.at("l1.misses").get<double>() / accesses : 0.0);
  s.set("report.node_dram_bytes_per_ray", node_bytes / rays);
  s.set("report.dram_bytes_per_frame", s.at("dram.bytes.total"));
  s.set("report.node_gbytes_per_second", node_bytes * fps / 1e9);
  s.set("report.dram_gbytes_per_second", total_bytes * fps / 1e9);
  s.set("trace.seconds", seconds);
  s.set("trace.rays_per_second", seconds > 0 ? rays / seconds : 0.0);
}

namespace {

// Traces the frame through `backend` (with a progress bar when `progress_bar`) on every core
// the tier allows, and times it.
FrameResult render_timed(const Prepared& p, TraceBackend& backend, const std::string& label,
                         bool progress_bar, double& seconds) {
  const int w = p.config.image.width, h = p.config.image.height;
  std::optional<ProgressBackend> progress;
  if (progress_bar) progress.emplace(backend, uint64_t(w) * h, label);
  TraceBackend& target = progress ? static_cast<TraceBackend&>(*progress) : backend;
  const std::vector<uint32_t> order = chip_pixel_order(p.config.chip, w, h);
  const auto t0 = std::chrono::steady_clock::now();
  FrameResult frame = parallel_render(p.scene, p.config.tracer, target,
                                      PinholeCamera(p.camera, w, h), w, h, order);
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return frame;
}

// One layout's run: its stats, pixel charges and frame, and the trace's seconds.
struct LayoutResult {
  LayoutRun run;
  FrameResult frame;
  double seconds = 0.0;
};

// A layout's result as bytes (MessagePack, which keeps every number's type and bits), for the
// child process that ran it to send to the parent.
std::string encode(const LayoutResult& r) {
  using nlohmann::json;
  const auto* radiance = reinterpret_cast<const uint8_t*>(r.frame.radiance.data());
  json j;
  j["kind"] = r.run.kind;
  j["stats"] = r.run.stats.to_json();
  j["pixel_dram_bytes"] = r.run.pixel_dram_bytes;
  j["width"] = r.frame.width;
  j["height"] = r.frame.height;
  j["radiance"] = json::binary(std::vector<uint8_t>(
      radiance, radiance + r.frame.radiance.size() * sizeof(glm::vec3)));
  j["rays_by_kind"] = r.frame.rays_by_kind;
  j["seconds"] = r.seconds;
  const std::vector<uint8_t> bytes = json::to_msgpack(j);
  return std::string(bytes.begin(), bytes.end());
}

LayoutResult decode(const std::string& bytes) {
  const nlohmann::json j = nlohmann::json::from_msgpack(bytes);
  LayoutResult r;
  r.run.kind = j.at("kind").get<std::string>();
  for (const auto& [k, v] : j.at("stats").items()) r.run.stats.set(k, v);
  r.run.pixel_dram_bytes = j.at("pixel_dram_bytes").get<std::vector<uint64_t>>();
  r.frame.width = j.at("width").get<int>();
  r.frame.height = j.at("height").get<int>();
  const std::vector<uint8_t>& radiance = j.at("radiance").get_binary();
  r.frame.radiance.resize(radiance.size() / sizeof(glm::vec3));
  std::memcpy(r.frame.radiance.data(), radiance.data(), radiance.size());
  r.frame.rays_by_kind = j.at("rays_by_kind").get<std::array<uint64_t, kRayKinds>>();
  r.seconds = j.at("seconds").get<double>();
  return r;
}

}  // namespace

SimulationResult simulate(const Prepared& p) {
  SimulationResult result;
  const int w = p.config.image.width, h = p.config.image.height;
  const FetchCacheParams caches = p.config.fetch_caches();
  const CycleParams cycle = p.config.cycle();
  // Sampled simulation (sample.*): the same units for every layout, one layout after another.
  std::optional<SampledFrame> sampler;
  if (p.config.sample.active()) sampler.emplace(p.config.sample, w, h, p.config.tracer.order);
  // Several layouts at once, up to --threads of them, on threads or in child processes as the
  // tier allows (each without a progress bar then).
  const bool concurrent = !sampler && p.images.size() > 1 && parallel_threads() > 1;
  const LayoutConcurrency how = tier_layout_concurrency(p.config.sim.tier);
  std::vector<LayoutResult> runs(p.images.size());
  auto run_layout = [&](size_t i) {
    // The same rays for every layout: hits do not depend on the layout, so neither do rays.
    const MemoryImage& image = p.images[i];
    LayoutRun& run = runs[i].run;
    run.kind = image.layout;
    add_image_stats(image, run.stats);
    // The tier's params for this layout: one VCD per layout when there are several.
    TierConfig tier_config{caches, p.config.functional, cycle, static_cast<uint32_t>(w * h),
                           static_cast<uint32_t>(w), p.config.chip};
    if (!cycle.vcd_path.empty() && p.images.size() > 1)
      tier_config.cycle.vcd_path = layout_vcd_path(cycle.vcd_path, image.layout);
    const std::unique_ptr<TierRun> tier = make_tier(p.config.sim.tier, image, tier_config);
    if (sampler) {
      runs[i].frame = sampler->render(p.scene, p.config.tracer, PinholeCamera(p.camera, w, h),
                                      *tier, image, image.layout, runs[i].seconds);
    } else {
      runs[i].frame = render_timed(p, tier->backend(), image.layout, !concurrent, runs[i].seconds);
    }
    tier->end_frame();
    tier->write_stats(run.stats);
    run.pixel_dram_bytes = tier->pixel_dram_bytes();
    tier->finish();
    if (sampler) sampler->finish_layout(runs[i].frame, run.stats);
  };
  if (concurrent && how == LayoutConcurrency::kThreads) {
    tbb::parallel_for(size_t{0}, p.images.size(), run_layout);
  } else if (concurrent) {
    // Each child elaborates its own top in a fresh SystemC context (CycleBackend). The parent
    // holds only the default context SystemC's library makes when it is loaded, with no module
    // in it, and no thread the child would miss (SystemC runs its processes as coroutines).
    std::vector<std::string> names;
    for (const MemoryImage& image : p.images) names.push_back("layout " + image.layout);
    const std::vector<std::string> bytes =
        run_in_child_processes(p.images.size(), parallel_threads(), names, [&](size_t i) {
          run_layout(i);
          return encode(runs[i]);
        });
    for (size_t i = 0; i < runs.size(); ++i) runs[i] = decode(bytes[i]);
  } else {
    for (size_t i = 0; i < p.images.size(); ++i) run_layout(i);
  }

  for (LayoutResult& lr : runs) {
    LayoutRun& run = lr.run;
    FrameResult& frame = lr.frame;
    if (!result.layouts.empty() &&
        (frame.rays_by_kind != result.frame.rays_by_kind ||
         std::memcmp(frame.radiance.data(), result.frame.radiance.data(),
                     frame.radiance.size() * sizeof(glm::vec3)) != 0))
      throw std::logic_error("layout " + run.kind + " changed the frame: a layout bug");
    add_report_stats(frame, p.config.report.frames_per_second, lr.seconds, run.stats);
    if (result.layouts.empty()) result.frame = std::move(frame);
    result.layouts.push_back(std::move(run));
  }

  add_run_stats(p, result.frame, result.stats);
  for (const auto& [k, v] : result.layouts.front().stats.values()) result.stats.set(k, v);
  if (result.layouts.size() > 1)
    for (const LayoutRun& run : result.layouts)
      for (const auto& [k, v] : run.stats.values()) result.stats.set("layout." + run.kind + "." + k, v);
  if (sampler) sampler->write_run_stats(result.stats);
  return result;
}

}  // namespace rtusim
