// The timed interleaved functional mode: one model per batch, or a batch in runs on every thread
// (see timed_interleaver.h).
#include "tier/timed_interleaver.h"

#include <algorithm>
#include <utility>

#include <oneapi/tbb/parallel_for.h>

#include "layout/layout_dispatch.h"
#include "tracer/chunk_pipeline.h"
#include "util/stat_decl.h"
#include "util/stats.h"

namespace rtusim {
namespace {
// Stats keys of the functional tier's timed mode.
const StatDecl kEstimateCycles("estimate.cycles", StatKind::kCounter, "cycles",
                               "the timed mode's estimate of the cycle tier's sim.cycles");
const StatDecl kEstimatePrimary("estimate.l1.primary_misses", StatKind::kCounter, "lines",
                                "its estimate of l1.primary_misses");
const StatDecl kEstimateMerged("estimate.l1.merged_misses", StatKind::kCounter, "lines",
                               "its estimate of l1.merged_misses");
const StatDecl kEstimateStalls("estimate.l1.mshr_stall_cycles", StatKind::kCounter, "cycles",
                               "its estimate of l1.mshr_stall_cycles");
const StatDecl kEstimateRuns("estimate.runs", StatKind::kProperty, "runs",
                             "runs of rays timed apart (functional.timed_segments > 1)");
}  // namespace


TimedInterleaver::TimedInterleaver(const MemoryImage& image, const CycleParams& timing,
                                   int rays_in_flight, int segments, int warmup_rays)
    : image_(image),
      timing_(timing),
      rays_in_flight_(rays_in_flight),
      segments_(static_cast<size_t>(std::max(segments, 1))),
      // The rays in flight at a cut must be a steady mix of old and new rays, not a batch's
      // first rays, all started at once: at least four times as many warming rays.
      warmup_rays_(std::max<size_t>(static_cast<size_t>(std::max(warmup_rays, 0)),
                                    4 * static_cast<size_t>(rays_in_flight))),
      engine_(std::make_unique<TimedEngine>(timing, rays_in_flight)) {}

TimedInterleaver::~TimedInterleaver() = default;

size_t TimedInterleaver::runs(size_t rays) const {
  // At least 8 W rays a run: the warming costs at most an eighth more.
  const size_t per_run = std::max<size_t>(8 * warmup_rays_, 1);
  return std::clamp<size_t>(rays / per_run, 1, segments_);
}

void TimedInterleaver::trace(std::span<const RayRecord> rays, std::span<Hit> hits,
                             FetchCache& caches, const Charge& charge) {
  const size_t k = runs(rays.size());
  if (k <= 1)
    trace_whole(rays, hits, caches, charge);
  else
    trace_runs(rays, hits, caches, charge, k);
}

void TimedInterleaver::add(const TimedEngine::Window& w) {
  cycles_ += w.cycles;
  primary_ += w.primary_misses;
  merged_ += w.merged_misses;
  stall_cycles_ += w.mshr_stall_cycles;
  ++runs_;
}

void TimedInterleaver::record(std::span<const RayRecord> rays, size_t begin, size_t end,
                              size_t first_hit, std::span<Hit> hits, RayStepLog& log,
                              StreamFetches* own_fetches) const {
  log.clear();
  // The own rays [first_hit, end) follow the warming ones: their fetches are the log's counts
  // past those it had when the first of them began.
  StreamFetches before_own{};
  with_layout_decoder(image_, [&]<class Decoder>() {
    for (size_t i = begin; i < end; ++i) {
      if (i == first_hit) before_own = log.fetches();
      const Hit h = log.record<Decoder>(image_, rays[i]);
      if (i >= first_hit) hits[i] = h;
    }
  });
  if (own_fetches && first_hit < end)
    for (size_t k = 0; k < before_own.size(); ++k)
      (*own_fetches)[k] += log.fetches()[k] - before_own[k];
}

void TimedInterleaver::trace_whole(std::span<const RayRecord> rays, std::span<Hit> hits,
                                   FetchCache& caches, const Charge& charge) {
  engine_->begin_batch(0, /*stop_at_end=*/false);
  const size_t chunks = (rays.size() + kRaysPerChunk - 1) / kRaysPerChunk;
  if (chunks <= 1) {
    record(rays, 0, rays.size(), 0, hits, log_);
    engine_->time(log_, /*last=*/true, caches, charge);
  } else {
    run_chunks<RayStepLog>(
        chunks,
        [&](size_t c, RayStepLog& log) {
          const size_t begin = c * kRaysPerChunk;
          record(rays, begin, std::min(begin + kRaysPerChunk, rays.size()), begin, hits, log);
        },
        [&](size_t c, RayStepLog& log) {
          engine_->time(log, c + 1 == chunks, caches, charge);
        });
  }
  add(engine_->window());
}

void TimedInterleaver::trace_runs(std::span<const RayRecord> rays, std::span<Hit> hits,
                                  FetchCache& caches, const Charge& charge, size_t k) {
  struct Run {
    size_t begin = 0, end = 0;  // its rays
    std::unique_ptr<TimedEngine> engine;
    std::unique_ptr<FetchCache> caches;  // run 0: the batch's own
    std::vector<std::pair<uint32_t, uint64_t>> charges;  // (pixel, DRAM bytes), in order
    StreamFetches own_fetches{};  // its own rays' fetches (not the warming rays')
  };
  const FetchCache::Counters before = caches.counters();
  std::vector<Run> runs(k);
  for (size_t j = 0; j < k; ++j) {
    Run& r = runs[j];
    r.begin = rays.size() * j / k;
    r.end = rays.size() * (j + 1) / k;
    if (j == 0) {
      r.engine = std::move(engine_);
    } else {
      r.engine = std::make_unique<TimedEngine>(timing_, rays_in_flight_);
      r.caches = std::make_unique<FetchCache>(caches);
    }
  }
  // Each run on its own thread: the rays before it (warming), then its own, traversed and
  // timed a chunk at a time.
  tbb::parallel_for(size_t{0}, k, [&](size_t j) {
    Run& r = runs[j];
    FetchCache& c = r.caches ? *r.caches : caches;
    const size_t from = r.begin - std::min(r.begin, j == 0 ? 0 : warmup_rays_);
    r.engine->begin_batch(r.begin - from, /*stop_at_end=*/j + 1 < k);
    const TimedEngine::Charge keep = [&](uint32_t pixel, uint64_t bytes) {
      r.charges.emplace_back(pixel, bytes);
    };
    RayStepLog log;
    for (size_t begin = from; begin < r.end; begin += kRaysPerChunk) {
      const size_t end = std::min(begin + kRaysPerChunk, r.end);
      record(rays, begin, end, r.begin, hits, log, &r.own_fetches);  // a warming ray's hit is another run's
      r.engine->time(log, end == r.end, c, keep);
    }
  });
  // In run order: the charges, the windows; the caches' counters grow by every run's window
  // (run 0's already did) and their lines become the last run's.
  FetchCache::Counters total = caches.counters();
  for (size_t j = 0; j < k; ++j) {
    for (const auto& [pixel, bytes] : runs[j].charges) charge(pixel, bytes);
    add(runs[j].engine->window());
    if (j > 0)
      for (int s = 0; s < FetchCache::kStreams; ++s)
        total[s] += runs[j].engine->window().counters[s];
  }
  // Fetch counts are the traversal's, not the cache model's: exact from the runs' own rays
  // (the windows count a fetch twice or not at all where a ray is in flight across a cut).
  for (int s = 0; s < FetchCache::kStreams; ++s) {
    total[s].fetches = before[s].fetches;
    for (const Run& r : runs) total[s].fetches += r.own_fetches[s];
  }
  caches.take_lines(*runs[k - 1].caches, total);
  engine_ = std::move(runs[k - 1].engine);
}

void TimedInterleaver::write_stats(Stats& stats) const {
  stats.set("estimate.cycles", cycles_);
  stats.set("estimate.l1.primary_misses", primary_);
  stats.set("estimate.l1.merged_misses", merged_);
  stats.set("estimate.l1.mshr_stall_cycles", stall_cycles_);
  if (segments_ > 1) stats.set("estimate.runs", runs_);
}

}  // namespace rtusim
