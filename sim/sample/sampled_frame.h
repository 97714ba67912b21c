// Sampled simulation of a frame. Recursive order: the drawn units are traced one after another
// through a tier's backend (each unit's pixels in scan order, optionally after unmeasured
// warming pixels). Wavefront order: the whole frame is traced generation by generation as in
// the full run, and only the drawn units' rays of each batch go through the tier
// (GenerationSampler). Either way every extensive figure is measured per unit as the change of
// the counters the tier writes (TierRun::write_stats before and after), and the stats get
// whole-frame estimates with 95% CIs. Every layout uses the same units; each pair of layouts
// gets paired-difference CIs. With sample.target_ci the first layout draws units in rounds
// until every figure (or sample.target_key) reaches it; the other layouts reuse those units.
#pragma once
#include <map>
#include <span>
#include <string>
#include <vector>

#include "sample/estimator.h"
#include "sample/sample_params.h"
#include "sample/unit_plan.h"
#include "scene/pinhole_camera.h"
#include "tier/tier.h"
#include "tracer/whitted_tracer.h"
#include "util/stats.h"

namespace rtusim {

class SampledFrame {
 public:
  // `order` is the tracer's.
  SampledFrame(const SampleParams& params, int width, int height, RayOrder order);

  // Traces this layout's sample of `scene` with `tracer` params, sending the measured rays to
  // tier.backend() (wavefront order: every ray's hit from plain traversal of `image`), and
  // keeps every unit's figures. Throws InputError for a sample.target_key the tier lacks.
  FrameResult render(const Scene& scene, const TracerParams& tracer, const PinholeCamera& camera,
                     TierRun& tier, const MemoryImage& image, const std::string& layout,
                     double& seconds);

  // Replaces the layout's extensive keys in `stats` (written by the tier from its sampled
  // counters) with whole-frame estimates and adds `<key>.ci95_low`/`.ci95_high`; the frame's
  // ray counts become the (rounded) estimates. Call after the tier wrote its stats.
  void finish_layout(FrameResult& frame, Stats& stats) const;

  // Run-wide keys: sample.* (units, fraction, achieved CI, validity, per_generation) and the
  // paired differences of every pair of layouts. Says on stderr when the CIs are not valid.
  void write_run_stats(Stats& stats) const;

  // Adds each counter's (util/stat_decl.h) change from `before` to `after` (the tier's stats
  // around a measured span) to `into`.
  static void add_extensive_change(const Stats& before, const Stats& after,
                                   std::map<std::string, double>& into);

 private:
  struct LayoutSample {
    std::string layout;
    std::map<std::string, std::vector<double>> values;  // key -> per-unit figure, drawing order
    std::vector<double> unit_rays;  // wavefront order: per-unit rays, the same order
    double frame_rays = 0.0;        // wavefront order: the whole frame's rays
    uint64_t rays_simulated = 0;
    uint64_t rays_warmed = 0;  // wavefront order: rays sent through the tier unmeasured
    double seconds = 0.0;
  };

  // Traces units [from, to) of the drawing order; appends their figures to `sample`.
  void trace_units(WhittedTracer& tracer, const PinholeCamera& camera, const TierRun& tier,
                   size_t from, size_t to, FrameResult& frame, LayoutSample& sample);
  // Wavefront order: traces the whole frame into `frame` and measures units [from, to) of the
  // drawing order per generation; appends their figures to `sample`.
  void trace_generations(const Scene& scene, const TracerParams& tracer,
                         const PinholeCamera& camera, TierRun& tier, const MemoryImage& image,
                         size_t from, size_t to, FrameResult& frame, LayoutSample& sample);
  // This round's units in scan order of their first pixel (the order their figures are kept).
  std::vector<uint32_t> round_units(size_t from, size_t to) const;
  // Whole-frame estimate of a figure measured per unit of `sample` (sample.estimator's).
  Estimate estimate(const LayoutSample& sample, const std::vector<double>& values) const;
  // Whole-frame estimate of the figure `key` of `sample`: estimate() of its per-unit values,
  // but in recursive order rays.primary is the pixel count, exactly, and rays.total that plus
  // the estimated other rays (wavefront order: every rays.* is exact, see finish_layout()).
  Estimate figure(const LayoutSample& sample, const std::string& key) const;
  // Largest relative half-width over the target figures, and the figure it belongs to.
  std::pair<double, std::string> widest_ci(const LayoutSample& sample) const;

  SampleParams params_;
  int width_, height_;
  RayOrder order_;
  UnitPlan plan_;
  Estimator estimator_;
  std::vector<size_t> rounds_;  // end of each round of drawn units, decided by the first layout
  std::vector<int> strata_taken_;
  std::vector<LayoutSample> layouts_;
};

}  // namespace rtusim
