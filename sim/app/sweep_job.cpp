#include "app/sweep_job.h"

#include <chrono>
#include <map>
#include <stdexcept>
#include <tuple>

#include "app/simulation.h"
#include "scene/pinhole_camera.h"
#include "sweep/sweep_backend.h"
#include "tracer/whitted_tracer.h"

namespace rtusim {
namespace {

using Row = std::map<std::string, nlohmann::json>;

auto cache_tuple(const CacheParams& c) {
  return std::make_tuple(c.size_bytes, c.assoc, c.line_bytes, c.policy, c.seed);
}

// Distinct cache configurations, and each point's index among them.
struct Configs {
  std::vector<CacheParams> list;
  size_t add(const CacheParams& c) {
    for (size_t i = 0; i < list.size(); ++i)
      if (cache_tuple(list[i]) == cache_tuple(c)) return i;
    list.push_back(c);
    return list.size() - 1;
  }
};

const char* const kStreamNames[3] = {"nodes", "lists", "triangles"};

// Sets the cache-dependent keys of one point into `row` (FetchCache::write_stats and the
// derived report figures of simulate()).
void set_cache_keys(Row& row, const SweepBackend& b, const CacheSweep& nodes, size_t node_cfg,
                    const CacheParams& l1, const CacheSweep* data, size_t data_cfg,
                    const CacheParams* dcache, double frames_per_second) {
  std::array<uint64_t, 3> acc{}, miss{}, bytes{};
  const auto na = nodes.accesses(node_cfg), nm = nodes.misses(node_cfg);
  acc[0] = na[0];
  miss[0] = nm[0];
  bytes[0] = nm[0] * l1.line_bytes;
  row["l1.accesses"] = acc[0];
  row["l1.hits"] = acc[0] - miss[0];
  row["l1.misses"] = miss[0];
  for (const char* k : {"dcache.accesses", "dcache.hits", "dcache.misses"}) row.erase(k);
  if (dcache) {
    const auto da = data->accesses(data_cfg), dm = data->misses(data_cfg);
    for (int s = 1; s < 3; ++s) {
      acc[s] = da[s];
      miss[s] = dm[s];
      bytes[s] = dm[s] * dcache->line_bytes;
    }
    row["dcache.accesses"] = acc[1] + acc[2];
    row["dcache.hits"] = acc[1] + acc[2] - miss[1] - miss[2];
    row["dcache.misses"] = miss[1] + miss[2];
  } else {
    for (int s = 1; s < 3; ++s) {
      acc[s] = miss[s] = b.direct_bursts(static_cast<Stream>(s));
      bytes[s] = miss[s] * FetchCache::kDramBurstBytes;
    }
  }
  for (int s = 0; s < 3; ++s) {
    const std::string stem = std::string("fetch.") + kStreamNames[s];
    row[stem + ".fetches"] = b.fetches(static_cast<Stream>(s));
    row[stem + ".accesses"] = acc[s];
    row[stem + ".hits"] = acc[s] - miss[s];
    row[stem + ".misses"] = miss[s];
    row[std::string("dram.bytes.") + kStreamNames[s]] = bytes[s];
  }
  row["dram.bytes.total"] = bytes[0] + bytes[1] + bytes[2];
  // The figures simulate() derives from the counters.
  const double rays = std::max(1.0, row.at("rays.total").get<double>());
  const double node_bytes = row.at("dram.bytes.nodes").get<double>();
  const double total_bytes = row.at("dram.bytes.total").get<double>();
  const double accesses = row.at("l1.accesses").get<double>();
  row["l1.miss_rate"] = accesses > 0 ? row.at("l1.misses").get<double>() / accesses : 0.0;
  row["report.node_dram_bytes_per_ray"] = node_bytes / rays;
  row["report.dram_bytes_per_frame"] = row.at("dram.bytes.total");
  row["report.node_gbytes_per_second"] = node_bytes * frames_per_second / 1e9;
  row["report.dram_gbytes_per_second"] = total_bytes * frames_per_second / 1e9;
}

nlohmann::json to_json_row(const Row& row) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [k, v] : row)
    if (!is_timing_key(k)) j[k] = v;
  return j;
}

// The keys of a one-layout run of layout `i` from a several-layout simulate().
Row one_layout_stats(const SimulationResult& r, size_t i) {
  Row row;
  const Stats& first = r.layouts.front().stats;
  for (const auto& [k, v] : r.stats.values()) {
    if (first.has(k)) continue;  // the first layout's copy
    bool prefixed = false;
    for (const LayoutRun& run : r.layouts)
      prefixed = prefixed || k.rfind("layout." + run.kind + ".", 0) == 0;
    if (!prefixed) row[k] = v;
  }
  for (const auto& [k, v] : r.layouts[i].stats.values()) row[k] = v;
  return row;
}

void run_functional(const SweepPlan& plan, const SweepJob& job, const std::string& base_path,
                    unsigned threads, nlohmann::json& rows) {
  // Prepare once for every layout of the job, with the first point's other keys.
  const SweepPoint& anchor = plan.points[job.points.front()];
  std::vector<std::string> kinds;
  for (const size_t i : job.points)
    if (std::find(kinds.begin(), kinds.end(), plan.points[i].layout) == kinds.end())
      kinds.push_back(plan.points[i].layout);
  std::vector<std::string> overrides = plan.sets;
  for (const auto& o : anchor.overrides)
    if (o.rfind("layout.kind=", 0) != 0) overrides.push_back(o);
  std::string list;
  for (const auto& k : kinds) list += (list.empty() ? "'" : ", '") + k + "'";
  overrides.push_back("layout.kind=[" + list + "]");
  const Prepared p = prepare_run(base_path, overrides);
  const SimulationResult ref = simulate(p);
  const int w = p.config.image.width, h = p.config.image.height;

  for (size_t li = 0; li < kinds.size(); ++li) {
    // The distinct caches of this layout's points (the anchor's first, for the self-check).
    Configs node_cfgs, data_cfgs;
    node_cfgs.add(p.config.fetch_caches().node_l1);
    if (p.config.fetch_caches().data_cache) data_cfgs.add(*p.config.fetch_caches().data_cache);
    std::vector<size_t> points;
    for (const size_t i : job.points)
      if (plan.points[i].layout == kinds[li]) {
        points.push_back(i);
        node_cfgs.add(plan.points[i].caches.node_l1);
        if (plan.points[i].caches.data_cache) data_cfgs.add(*plan.points[i].caches.data_cache);
      }
    const MemoryImage& image = p.images[li];
    CacheSweep nodes(node_cfgs.list, image.bytes.size());
    std::optional<CacheSweep> data;
    if (!data_cfgs.list.empty()) data.emplace(data_cfgs.list, image.bytes.size());
    nodes.set_threads(threads);
    if (data) data->set_threads(threads);
    SweepBackend backend(image, nodes, data ? &*data : nullptr);
    WhittedTracer tracer(p.scene, p.config.tracer, backend);
    tracer.render(PinholeCamera(p.camera, w, h), w, h);
    backend.flush();

    const Row base_row = one_layout_stats(ref, li);
    const double fps = p.config.report.frames_per_second;
    const auto row_for = [&](const FetchCacheParams& c) {
      Row row = base_row;
      const CacheParams* dc = c.data_cache ? &*c.data_cache : nullptr;
      set_cache_keys(row, backend, nodes, node_cfgs.add(c.node_l1), c.node_l1,
                     data ? &*data : nullptr,
                     dc ? data_cfgs.add(*dc) : 0, dc, fps);
      return row;
    };
    // Self-check: the one-pass counts of the reference cache are simulate()'s.
    if (to_json_row(row_for(p.config.fetch_caches())) != to_json_row(base_row))
      throw std::logic_error("sweep: the one-pass cache counts of layout " + kinds[li] +
                             " differ from simulate()'s");
    for (const size_t i : points) rows[std::to_string(i)] = to_json_row(row_for(plan.points[i].caches));
  }
}

}  // namespace

bool is_timing_key(const std::string& key) {
  const auto ends = [&](const std::string& s) {
    return key.size() >= s.size() && key.compare(key.size() - s.size(), s.size(), s) == 0;
  };
  return ends("seconds") || key == "trace.rays_per_second";
}

nlohmann::json run_sweep_job(const SweepPlan& plan, size_t job, const std::string& base_path,
                             unsigned threads) {
  const auto t0 = std::chrono::steady_clock::now();
  const SweepJob& j = plan.jobs.at(job);
  nlohmann::json rows = nlohmann::json::object();
  if (j.timed) {
    const SweepPoint& pt = plan.points[j.points.front()];
    std::vector<std::string> overrides = plan.sets;
    overrides.insert(overrides.end(), pt.overrides.begin(), pt.overrides.end());
    const Prepared p = prepare_run(base_path, overrides);
    const SimulationResult r = simulate(p);
    Row row(r.stats.values().begin(), r.stats.values().end());
    rows[std::to_string(j.points.front())] = to_json_row(row);
  } else {
    run_functional(plan, j, base_path, threads, rows);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return {{"job", job}, {"points", j.points.size()}, {"seconds", seconds}, {"rows", rows}};
}

}  // namespace rtusim
