// The L1 timing and model keys, and the validation of L1 parameters.
#include "mem/l1_params.h"

#include "cache/cache_config.h"
#include "config/param.h"
#include "util/error.h"

namespace rtusim {
namespace {

const L1Params kDefaults;
const CacheLevelKeys kL1Keys("l1", "node L1");
const CacheLevelKeys kDcacheKeys("dcache", "list/triangle cache");
const BoolParam kDcacheEnable("dcache.enable", false,
                              "list/triangle cache on (false: lists and triangles straight to DRAM)");
const IntParam kL1HitCycles("l1.hit_cycles", kDefaults.hit_cycles, 1, 1 << 20, "cycles",
                            "node L1 hit latency (l1.model = rtl: 2)");
const IntParam kL1Mshrs("l1.mshrs", kDefaults.mshrs, 1, 4096, "",
                        "node L1 outstanding line misses (l1.model = rtl: 8)");
const StringParam kL1Model("l1.model", "cpp", {"cpp", "rtl"}, "",
                           "node L1 model of the cycle tier: cpp, or rtl (the Verilated "
                           "rtl_model/l1_cache.sv; built geometries only)");
const IntParam kDcacheHitCycles("dcache.hit_cycles", kDefaults.hit_cycles, 1, 1 << 20, "cycles",
                                "list/triangle cache hit latency");
const IntParam kDcacheMshrs("dcache.mshrs", kDefaults.mshrs, 1, 4096, "",
                            "list/triangle cache outstanding line misses");

}  // namespace

void validate(const L1Params& p, const std::string& prefix) {
  validate(p.cache, prefix);
  validate_timing(p, prefix);
}

void validate_timing(const L1Params& p, const std::string& prefix) {
  if (p.hit_cycles == 0) throw KeyError(prefix + ".hit_cycles", "must be at least 1");
  if (p.mshrs == 0) throw KeyError(prefix + ".mshrs", "must be at least 1");
  if (p.clock_period_ps == 0) throw KeyError("sim.clock_mhz", "must be positive");
}

CacheParams read_node_l1_geometry(ConfigReader& r) { return kL1Keys.read(r); }

L1Config read_node_l1_config(ConfigReader& r) {
  L1Config c;
  c.params.cache = kL1Keys.read(r);
  c.params.hit_cycles = static_cast<uint32_t>(kL1HitCycles.read(r));
  c.params.mshrs = static_cast<uint32_t>(kL1Mshrs.read(r));
  c.model = kL1Model.read(r);
  return c;
}

L1Config read_dcache_config(ConfigReader& r) {
  L1Config c;
  c.enable = kDcacheEnable.read(r);
  c.params.cache = kDcacheKeys.read(r);
  c.params.hit_cycles = static_cast<uint32_t>(kDcacheHitCycles.read(r));
  c.params.mshrs = static_cast<uint32_t>(kDcacheMshrs.read(r));
  return c;
}

}  // namespace rtusim
