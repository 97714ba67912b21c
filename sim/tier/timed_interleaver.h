// The interleaved functional mode with approximate time (functional.timed = true): the rays in
// flight take their traversal steps in the order of a cheap model of the unit's timing
// (TimedEngine), not in strict turns, so rays whose nodes hit overtake rays that wait for DRAM
// as in the cycle tier; it estimates the cycle tier's cycles.
//
// One batch, one model (functional.timed_segments = 1): the batch's rays are traversed in
// chunks on every thread and the model goes over their records on one thread, from where the
// previous batch left it.
//
// In segments (functional.timed_segments = K > 1): the model itself is serial, so a batch of
// n rays is cut into k = min(K, n / (8 x functional.timed_warmup_rays)) runs of consecutive
// rays, each timed by its own model on any thread. Run j > 0 starts with a fresh model and a
// copy of the caches as they were at the batch's start, times the W rays before it unmeasured
// (they fill the rays in flight, the L1 and the DRAM's rows; W is at least 4 x the rays in
// flight, so those in flight at the cut are a steady mix), and measures from the moment its
// first ray starts to the moment its rays run out (the next run's first ray would start); the
// last run measures to its last ray's end. The batch's cache, DRAM and time figures are the sum
// of the runs' windows (the cycles too: the windows tile the batch's time), so they approximate
// the one-model run's to within what W warming rays miss at each of the k - 1 cuts; its fetch
// counts are its rays' own, exactly (each run counts the rays it measures); the next batch goes on from the
// last run's model and caches. k depends on the batch and the keys only, never on the threads:
// the figures are the same for any thread count.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "cache/fetch_cache.h"
#include "layout/memory_image.h"
#include "model/cycle_params.h"
#include "tier/timed_engine.h"
#include "traversal/ray_step_log.h"
#include "tracer/trace_backend.h"

namespace rtusim {

class Stats;

class TimedInterleaver {
 public:
  using Charge = TimedEngine::Charge;
  // `timing` derived (CycleParams::derive()); `image` must outlive the interleaver. `segments`
  // (K) and `warmup_rays` (W): above.
  TimedInterleaver(const MemoryImage& image, const CycleParams& timing, int rays_in_flight,
                   int segments = 1, int warmup_rays = 256);
  ~TimedInterleaver();

  // Traces a batch through `caches`; calls charge(pixel, DRAM bytes) with the bytes each ray's
  // fetches caused. Time goes on from the previous batch's end.
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits, FetchCache& caches,
             const Charge& charge);

  // The runs of a batch of `rays` rays (1: one model).
  size_t runs(size_t rays) const;
  // functional.timed_segments (K).
  size_t segments() const { return segments_; }
  // estimate.cycles, estimate.l1.{primary,merged}_misses, estimate.l1.mshr_stall_cycles,
  // estimate.runs (models run: one per batch, k per batch in segments).
  void write_stats(Stats& stats) const;

 private:
  // The batch through one model (engine_), traversed on every thread.
  void trace_whole(std::span<const RayRecord> rays, std::span<Hit> hits, FetchCache& caches,
                   const Charge& charge);
  // The batch in k runs on any thread.
  void trace_runs(std::span<const RayRecord> rays, std::span<Hit> hits, FetchCache& caches,
                  const Charge& charge, size_t k);
  using StreamFetches = RayStepLog::StreamFetches;
  // Records rays [begin, end) into `log` (cleared first); the hits of those from first_hit on
  // into hits, and their fetches added to *own_fetches when given.
  void record(std::span<const RayRecord> rays, size_t begin, size_t end, size_t first_hit,
              std::span<Hit> hits, RayStepLog& log, StreamFetches* own_fetches = nullptr) const;
  void add(const TimedEngine::Window& w);

  const MemoryImage& image_;
  CycleParams timing_;
  int rays_in_flight_;
  size_t segments_, warmup_rays_;
  std::unique_ptr<TimedEngine> engine_;  // where the next batch goes on
  RayStepLog log_;  // a batch of one chunk: recorded and timed on this thread
  // The windows' sums.
  uint64_t cycles_ = 0, primary_ = 0, merged_ = 0, stall_cycles_ = 0, runs_ = 0;
};

}  // namespace rtusim
