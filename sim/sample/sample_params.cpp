#include "sample/sample_params.h"

#include "config/config_reader.h"
#include "sample/sampled_frame.h"
#include "util/error.h"

namespace rtusim {

SampleParams read_sample_params(ConfigReader& r) {
  SampleParams s;
  s.rate = r.get_float("sample.rate", 1.0, 1e-9, 1.0);
  s.method_name = r.get_string("sample.method", "tiles", {"random", "stratified", "tiles"});
  s.method = s.method_name == "random"       ? SampleMethod::kRandom
             : s.method_name == "stratified" ? SampleMethod::kStratified
                                             : SampleMethod::kTiles;
  s.seed = static_cast<uint64_t>(r.get_int("sample.seed", 1, 0, int64_t{1} << 62));
  s.target_ci = r.get_float("sample.target_ci", 0.0, 0.0, 0.999);
  s.target_key = r.get_string("sample.target_key", "");
  if (!s.target_key.empty() && !SampledFrame::is_extensive(s.target_key))
    throw InputError(r.origin() + ": sample.target_key: '" + s.target_key +
                     "' is not an extensive figure (e.g. dram.bytes.nodes, sim.cycles)");
  s.warmup_name = r.get_string("sample.warmup", "functional", {"none", "functional"});
  s.warmup = s.warmup_name == "none" ? SampleWarmup::kNone : SampleWarmup::kFunctional;
  s.warmup_pixels = static_cast<int>(r.get_int("sample.warmup_pixels", 64, 0, 1 << 24));
  s.unit_pixels = static_cast<int>(r.get_int("sample.unit_pixels", 32, 1, 1 << 20));
  // Strata by default only for the stratified method: with tiles they narrow the CIs a little
  // but cost coverage in heavy-tailed scenes (docs/accuracy.md).
  s.strata = static_cast<int>(
      r.get_int("sample.strata", s.method == SampleMethod::kStratified ? 4 : 1, 1, 256));
  s.min_units = static_cast<int>(r.get_int("sample.min_units", 30, 2, 1 << 24));
  s.origin = r.origin();
  return s;
}

}  // namespace rtusim
