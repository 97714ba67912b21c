// The sample.* keys, declared here and read in one pass.
#include "sample/sample_params.h"

#include "config/param.h"
#include "sample/sampled_frame.h"
#include "util/error.h"
#include "util/stat_decl.h"

namespace rtusim {
namespace {

const SampleParams kSample;
const FloatParam kRate("sample.rate", kSample.rate, 1e-9, 1.0, "",
                       "share of the frame's units simulated (1: off, unless "
                       "sample.target_ci; with it, the cap)");
const StringParam kMethod("sample.method", kSample.method_name, {"random", "stratified", "tiles"},
                          "",
                          "units: random pixels, random pixels drawn per block of the strata "
                          "grid, or tiles (adjacent pixels of one row)");
const IntParam kSeed("sample.seed", int64_t(kSample.seed), 0, int64_t{1} << 62, "",
                     "seed of the units' drawing");
const FloatParam kTargetCi("sample.target_ci", kSample.target_ci, 0.0, 0.999, "",
                           "relative 95% CI half-width to reach, drawing units in rounds "
                           "(0: off)");
const StringParam kTargetKey("sample.target_key", kSample.target_key, {}, "",
                             "the extensive figure sample.target_ci applies to (\"\": every "
                             "one)");
const StringParam kWarmup("sample.warmup", kSample.warmup_name, {"none", "functional"}, "",
                          "functional: trace sample.warmup_pixels pixels (wavefront order: "
                          "sample.warmup_rays rays) unmeasured before each run of a unit's "
                          "pixels (rays)");
const IntParam kWarmupPixels("sample.warmup_pixels", kSample.warmup_pixels, 0, 1 << 24, "pixels",
                             "recursive order: pixels traced unmeasured before each run of a "
                             "unit's pixels");
const IntParam kWarmupRays("sample.warmup_rays", kSample.warmup_rays, 0, 1 << 24, "rays",
                            "wavefront order: rays of the frame's sequence traced unmeasured "
                            "before each run of a unit's rays in a generation's batch");
const IntParam kUnitPixels("sample.unit_pixels", kSample.unit_pixels, 1, 1 << 20, "pixels",
                           "pixels per sampling unit");
const IntParam kStrata("sample.strata", kSample.strata, 1, 256, "",
                       "side of the strata grid (strata x strata blocks); 4 by default with "
                       "sample.method = stratified");
const StringParam kEstimator("sample.estimator", kSample.estimator_name, {"mean", "ratio"}, "",
                              "mean: the units' mean figure x the frame's units; ratio: the "
                              "units' figure per ray x the frame's rays, narrower where cost "
                              "follows rays (needs tracer.ray_order = wavefront)");
const IntParam kMinUnits("sample.min_units", kSample.min_units, 2, 1 << 24, "units",
                         "fewer units than this: the CIs are flagged as not valid");

// The stratified method's default strata grid side.
constexpr int kStratifiedStrata = 4;

}  // namespace

SampleParams read_sample_params(ConfigReader& r, RayOrder order) {
  SampleParams s;
  s.rate = kRate.read(r);
  s.method_name = kMethod.read(r);
  s.method = s.method_name == "random"       ? SampleMethod::kRandom
             : s.method_name == "stratified" ? SampleMethod::kStratified
                                             : SampleMethod::kTiles;
  s.seed = static_cast<uint64_t>(kSeed.read(r));
  s.target_ci = kTargetCi.read(r);
  s.target_key = kTargetKey.read(r);
  if (!s.target_key.empty() && !is_counter_key(s.target_key))
    r.fail(KeyError(kTargetKey.key(), "'" + s.target_key +
                                          "' is not a counter (e.g. dram.bytes.nodes, "
                                          "sim.cycles)"));
  s.warmup_name = kWarmup.read(r);
  s.warmup = s.warmup_name == "none" ? SampleWarmup::kNone : SampleWarmup::kFunctional;
  s.warmup_pixels = static_cast<int>(kWarmupPixels.read(r));
  s.warmup_rays = static_cast<int>(kWarmupRays.read(r));
  s.unit_pixels = static_cast<int>(kUnitPixels.read(r));
  // Strata by default only for the stratified method: with tiles they narrow the CIs a little
  // but cost coverage in heavy-tailed scenes (docs/accuracy.md).
  s.strata = static_cast<int>(
      kStrata.read(r, s.method == SampleMethod::kStratified ? kStratifiedStrata : kSample.strata));
  s.min_units = static_cast<int>(kMinUnits.read(r));
  s.estimator_name = kEstimator.read(r);
  s.estimator = s.estimator_name == "ratio" ? SampleEstimator::kRatio : SampleEstimator::kMean;
  // Only the wavefront order traces the whole frame, so only there are the frame's rays known.
  if (s.estimator == SampleEstimator::kRatio && order != RayOrder::kWavefront)
    r.fail(KeyError({kEstimator.key(), "tracer.ray_order"},
                    "\"ratio\" needs tracer.ray_order = \"wavefront\" (in recursive order the "
                    "frame's rays are not traced, so not known)"));
  s.target_key_origin = r.where("sample.target_key");
  return s;
}

}  // namespace rtusim
