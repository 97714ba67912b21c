#include "app/sweep_job.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <optional>
#include <tuple>

#include "app/simulation.h"
#include "chip/ray_dealer.h"
#include "scene/pinhole_camera.h"
#include "sweep/l2_lru_sweep.h"
#include "sweep/sweep_backend.h"
#include "tier/chip_functional_backend.h"
#include "tier/functional_tier.h"
#include "tracer/parallel_render.h"
#include "tracer/whitted_tracer.h"
#include "util/stat_decl.h"
#include "util/stats.h"

namespace rtusim {
namespace {

auto cache_tuple(const CacheParams& c) {
  return std::make_tuple(c.size_bytes, c.assoc, c.line_bytes, c.policy, c.seed);
}

// Distinct cache configurations: add() gives a configuration's index, adding it when new.
struct Configs {
  std::vector<CacheParams> list;
  std::map<decltype(cache_tuple(CacheParams{})), size_t> index;
  size_t add(const CacheParams& c) {
    const auto [it, added] = index.try_emplace(cache_tuple(c), list.size());
    if (added) list.push_back(c);
    return it->second;
  }
};

// The streams' counters of one point: the node stream through node configuration `node_cfg`,
// lists and triangles through data configuration `data_cfg` or straight to DRAM.
FetchCache::Counters point_counters(const SweepBackend& b, const CacheSweep& nodes, size_t node_cfg,
                                    const CacheParams& l1, const CacheSweep* data,
                                    size_t data_cfg, const CacheParams* dcache) {
  FetchCache::Counters c{};
  const auto count = [&](int s, uint64_t accesses, uint64_t misses, uint32_t line_bytes) {
    c[s].accesses = accesses;
    c[s].hits = accesses - misses;
    c[s].misses = misses;
    c[s].dram_bytes = misses * line_bytes;
  };
  count(0, nodes.accesses(node_cfg)[0], nodes.misses(node_cfg)[0], l1.line_bytes);
  for (int s = 1; s < FetchCache::kStreams; ++s) {
    if (dcache)
      count(s, data->accesses(data_cfg)[s], data->misses(data_cfg)[s], dcache->line_bytes);
    else
      count(s, b.direct_bursts(Stream(s)), b.direct_bursts(Stream(s)), b.dram_burst_bytes());
  }
  for (int s = 0; s < FetchCache::kStreams; ++s) c[s].fetches = b.fetches(Stream(s));
  return c;
}

nlohmann::json to_json_row(const Stats& stats) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [k, v] : stats.values())
    if (!is_timing_key(k)) j[k] = v;
  return j;
}

// The job's run prepared once for every layout of its points (`kinds`, in point order), with
// its first point's other keys.
Prepared prepare_job(const SweepPlan& plan, const SweepJob& job, const std::string& base_path,
                     std::vector<std::string>& kinds) {
  const SweepPoint& anchor = plan.points[job.points.front()];
  for (const size_t i : job.points)
    if (std::find(kinds.begin(), kinds.end(), plan.points[i].layout) == kinds.end())
      kinds.push_back(plan.points[i].layout);
  std::vector<std::string> overrides = plan.sets;
  for (const auto& o : anchor.overrides)
    if (o.rfind("layout.kind=", 0) != 0) overrides.push_back(o);
  std::string list;
  for (const auto& k : kinds) list += (list.empty() ? "'" : ", '") + k + "'";
  overrides.push_back("layout.kind=[" + list + "]");
  return prepare_run(base_path, overrides);
}

void run_functional(const SweepPlan& plan, const SweepJob& job, const std::string& base_path,
                    unsigned threads, nlohmann::json& rows) {
  std::vector<std::string> kinds;
  const Prepared p = prepare_job(plan, job, base_path, kinds);
  const int w = p.config.image.width, h = p.config.image.height;

  for (size_t li = 0; li < kinds.size(); ++li) {
    // The distinct caches of this layout's points, and each point's indices among them.
    struct PointCaches {
      size_t point, node_cfg, data_cfg;
    };
    Configs node_cfgs, data_cfgs;
    std::vector<PointCaches> points;
    for (const size_t i : job.points)
      if (plan.points[i].layout == kinds[li]) {
        const FetchCacheParams& c = plan.points[i].caches;
        points.push_back({i, node_cfgs.add(c.node_l1), c.data_cache ? data_cfgs.add(*c.data_cache) : 0});
      }
    if (points.empty()) continue;
    // One traced frame: every cache of the layout evaluated as the fetches come.
    const MemoryImage& image = p.images[li];
    CacheSweep nodes(node_cfgs.list, image.bytes.size(),
                     CacheSweep::parts_for(node_cfgs.list, threads));
    std::optional<CacheSweep> data;
    if (!data_cfgs.list.empty())
      data.emplace(data_cfgs.list, image.bytes.size(), CacheSweep::parts_for(data_cfgs.list, threads));
    // The job's points differ only in cache keys (sweep_plan's is_cache_key): one DRAM burst.
    SweepBackend backend(image, nodes, data ? &*data : nullptr, threads,
                         plan.points[points.front().point].caches.dram_burst_bytes);
    WhittedTracer tracer(p.scene, p.config.tracer, backend);
    const auto t0 = std::chrono::steady_clock::now();
    const FrameResult frame = tracer.render(PinholeCamera(p.camera, w, h), w, h);
    backend.flush();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    // Each point's stats.json keys, written by the code simulate() and the functional tier use.
    Stats base;
    add_run_stats(p, frame, base);
    add_image_stats(image, base);
    for (const PointCaches& pc : points) {
      const FetchCacheParams& c = plan.points[pc.point].caches;
      const CacheParams* dc = c.data_cache ? &*c.data_cache : nullptr;
      Stats stats = base;
      FunctionalTier::write_stats(point_counters(backend, nodes, pc.node_cfg, c.node_l1,
                                                 data ? &*data : nullptr, pc.data_cfg, dc),
                                  dc != nullptr, stats);
      add_report_stats(frame, p.config.report.frames_per_second, seconds, stats);
      rows[std::to_string(pc.point)] = to_json_row(stats);
    }
  }
}

// A job of chip points that differ only in their LRU L2 (and layout): per layout, the frame
// traced once through the units' caches with the first point's L2, the L2's requests fed to
// every point's L2 at once (L2LruSweep), and each point's stats written by the functional
// tier's chip writer from its L2's counts.
void run_l2_family(const SweepPlan& plan, const SweepJob& job, const std::string& base_path,
                   nlohmann::json& rows) {
  std::vector<std::string> kinds;
  const Prepared p = prepare_job(plan, job, base_path, kinds);
  const int w = p.config.image.width, h = p.config.image.height;
  const ChipParams& chip = p.config.chip;
  const std::vector<uint32_t> order = chip_pixel_order(chip, w, h);

  for (size_t li = 0; li < kinds.size(); ++li) {
    std::vector<size_t> points;
    std::vector<CacheParams> l2s;
    for (const size_t i : job.points)
      if (plan.points[i].layout == kinds[li]) {
        points.push_back(i);
        l2s.push_back(*plan.points[i].chip.l2);
      }
    if (points.empty()) continue;
    const MemoryImage& image = p.images[li];
    ChipFunctionalBackend backend(image, p.config.fetch_caches(), chip,
                                  static_cast<uint32_t>(w), static_cast<uint32_t>(w * h));
    L2LruSweep l2_sweep(l2s, chip.units, image.bytes.size());
    backend.chip().observe_l2([&](const NextLevelRequest& r, uint32_t unit) {
      l2_sweep.access(unit, r.stream, r.addr, r.bytes);
    });
    const auto t0 = std::chrono::steady_clock::now();
    const FrameResult frame = parallel_render(p.scene, p.config.tracer, backend,
                                              PinholeCamera(p.camera, w, h), w, h, order);
    backend.end_frame();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    Stats base;
    add_run_stats(p, frame, base);
    add_image_stats(image, base);
    const ChipL2Counts& taken = backend.chip().l2_counts();  // bytes in: the same for every L2
    for (size_t k = 0; k < points.size(); ++k) {
      ChipL2Counts l2;
      l2.units.resize(chip.units);
      for (uint32_t u = 0; u < chip.units; ++u)
        for (int s = 0; s < FetchCache::kStreams; ++s) {
          const L2LruSweep::Counts c = l2_sweep.counts(k, u, static_cast<Stream>(s));
          const uint64_t dram_bytes = c.misses * l2s[k].line_bytes;
          for (L2Counters* into : {&l2.streams[s], &l2.units[u]}) {
            into->accesses += c.accesses;
            into->hits += c.accesses - c.misses;
            into->misses += c.misses;
            into->dram_bytes += dram_bytes;
          }
        }
      for (int s = 0; s < FetchCache::kStreams; ++s) l2.streams[s].bytes_in = taken.streams[s].bytes_in;
      for (uint32_t u = 0; u < chip.units; ++u) l2.units[u].bytes_in = taken.units[u].bytes_in;
      Stats stats = base;
      FunctionalTier::write_chip_stats(backend.chip(), l2, stats);
      add_report_stats(frame, p.config.report.frames_per_second, seconds, stats);
      rows[std::to_string(points[k])] = to_json_row(stats);
    }
  }
}

}  // namespace

nlohmann::json run_sweep_job(const SweepPlan& plan, size_t job, const std::string& base_path,
                             unsigned threads) {
  const auto t0 = std::chrono::steady_clock::now();
  const SweepJob& j = plan.jobs.at(job);
  nlohmann::json rows = nlohmann::json::object();
  if (j.alone) {
    const SweepPoint& pt = plan.points[j.points.front()];
    std::vector<std::string> overrides = plan.sets;
    overrides.insert(overrides.end(), pt.overrides.begin(), pt.overrides.end());
    const Prepared p = prepare_run(base_path, overrides);
    rows[std::to_string(j.points.front())] = to_json_row(simulate(p).stats);
  } else if (j.l2_family) {
    run_l2_family(plan, j, base_path, rows);
  } else {
    run_functional(plan, j, base_path, threads, rows);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return {{"job", job}, {"points", j.points.size()}, {"seconds", seconds}, {"rows", rows}};
}

}  // namespace rtusim
