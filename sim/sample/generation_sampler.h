// Sampled simulation in wavefront order, one generation at a time: the tracer renders the whole
// frame in wavefront order through this backend, so every batch (a generation's rays of the
// whole frame, or their shadow rays) is the full run's batch. Every ray's hit comes from plain
// traversal; the drawn units' rays -- runs of consecutive rays of a batch, since a batch keeps
// the pixels' scan order -- also go through the tier, each run after the rays that precede it
// in the frame's ray sequence (at most `warm_rays`, unmeasured), and are measured as the change
// of the tier's counters. A unit's figure is its runs' sum over all generations: its share of
// the full run's total, so the expansion estimator over units stays unbiased for the frame.
//
// The plain traversal of a batch runs on the worker threads while the calling thread sends the
// batch's runs through the tier (the tier's work does not wait for the plain hits; they are
// compared with the tier's once both are done).
//
// The cut at a run's ends is explicit: each run (and each warming span) is a trace() call of
// its own, so a tier with rays in flight starts the run with an empty unit and drains it at the
// end, where the full run overlaps the run's first and last rays with its neighbours'.
#pragma once
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "tier/tier.h"
#include "tracer/trace_backend.h"

namespace rtusim {

class GenerationSampler final : public TraceBackend {
 public:
  // `plain` gives every ray's hit; `unit_of_pixel[p]` is the drawn unit (0..units-1) pixel p
  // belongs to, or -1; `warm_rays` = 0 is no warming.
  GenerationSampler(TraceBackend& plain, TierRun& tier, std::vector<int32_t> unit_of_pixel,
                    int units, int warm_rays);

  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override;

  // Each drawn unit's extensive figures (key -> sum over its runs), and rays.* it traced.
  const std::vector<std::map<std::string, double>>& unit_values() const { return values_; }
  // Each drawn unit's rays (over all generations).
  const std::vector<double>& unit_rays() const { return rays_; }
  uint64_t rays_measured() const { return rays_measured_; }
  uint64_t rays_warmed() const { return rays_warmed_; }

 private:
  // Warms the tier with the rays of the frame's sequence before batch ray `first` that the tier
  // has not just traced, at most warm_rays_ of them. Their hits from the tier: those of earlier
  // batches checked at once, those of this batch kept in tier_hits_ to be checked.
  void warm(std::span<const RayRecord> batch, size_t first);
  // Throws unless the tier's hits equal plain traversal's.
  static void check(std::span<const Hit> tier, std::span<const Hit> plain);

  TraceBackend& plain_;
  TierRun& tier_;
  std::vector<int32_t> unit_of_pixel_;
  int warm_rays_;
  std::vector<std::map<std::string, double>> values_;
  std::vector<double> rays_;
  uint64_t rays_measured_ = 0;
  uint64_t rays_warmed_ = 0;
  uint64_t batch_start_ = 0;   // sequence index of the current batch's first ray
  uint64_t next_unsent_ = 0;   // sequence index after the last ray the tier traced
  std::vector<RayRecord> tail_;  // the last warm_rays_ rays of the previous batches
  std::vector<Hit> tail_hits_;
  std::vector<Hit> scratch_;
  // The current batch's spans the tier traced, and their hits from it (one after another).
  struct Sent {
    size_t begin, end;  // in the batch
    size_t hits;        // the first one's in tier_hits_
  };
  std::vector<Sent> sent_;
  std::vector<Hit> tier_hits_;
  // Room for `n` more of the tier's hits (a span at the end of tier_hits_).
  std::span<Hit> tier_hits_room(size_t n);
};

}  // namespace rtusim
