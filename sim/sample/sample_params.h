// The keys of sampled simulation (sample.*): which share of the frame is simulated, in which
// units, how they are drawn, and when a run with an accuracy target may stop.
#pragma once
#include <cstdint>
#include <string>

#include "tracer/tracer_params.h"

namespace rtusim {

class ConfigReader;

enum class SampleMethod {
  kRandom,      // units of sample.unit_pixels pixels drawn at random from the whole frame
  kStratified,  // the same, drawn in proportion from a sample.strata x sample.strata grid of blocks
  kTiles,       // units of sample.unit_pixels adjacent pixels of one row (the scan order's
                // coherence), drawn in proportion from the same grid's blocks
};

enum class SampleEstimator {
  kMean,   // expansion: the units' mean figure x the frame's units
  kRatio,  // ratio: the units' figure per ray x the frame's rays (wavefront order, where the
           // whole frame is traced and its rays are known)
};

enum class SampleWarmup {
  kNone,        // a unit starts with whatever the previous unit left in the caches
  kFunctional,  // the sample.warmup_pixels pixels before each run of a unit's pixels (wavefront
                // order: the sample.warmup_rays rays before each run of a unit's rays in a
                // batch) are traced first, unmeasured (SMARTS-style warming of the caches)
};

struct SampleParams {
  double rate = 1.0;        // share of the frame's units simulated (1 = off, unless target_ci)
  SampleMethod method = SampleMethod::kTiles;
  std::string method_name = "tiles";
  uint64_t seed = 1;
  double target_ci = 0.0;   // relative 95% half-width to reach; 0 = off (rate is then the cap)
  std::string target_key;   // the figure target_ci applies to; "" = every extensive figure
  SampleWarmup warmup = SampleWarmup::kFunctional;
  std::string warmup_name = "functional";
  int warmup_pixels = 64;   // pixels traced unmeasured before each run of a unit's pixels
  int warmup_rays = 128;    // wavefront order: rays traced unmeasured before each run of a
                            // unit's rays in a batch
  int unit_pixels = 32;     // pixels per sampling unit
  int strata = 1;           // the strata grid's side (strata x strata blocks); the stratified
                            // method's default is 4
  int min_units = 30;       // fewer units than this: the CIs are flagged as not valid
  SampleEstimator estimator = SampleEstimator::kMean;
  std::string estimator_name = "mean";
  std::string target_key_origin;  // where target_key came from (its --set, or file:line), for
                                  // the error found while running

  bool active() const { return rate < 1.0 || target_ci > 0.0; }
};

// Reads sample.* (every key, so they are validated and in the effective config); `order` is
// the tracer's (sample.estimator = "ratio" needs the wavefront order).
SampleParams read_sample_params(ConfigReader& r, RayOrder order);

}  // namespace rtusim
