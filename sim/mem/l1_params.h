// Parameters of an L1 (the node L1, or the list/triangle data cache): geometry, timing and the
// model, and the config keys they come from (declared in l1_params.cpp):
//   l1.hit_cycles, l1.mshrs, l1.model; dcache.hit_cycles, dcache.mshrs (geometry: cache_config.h)
#pragma once
#include <cstdint>
#include <string>

#include "cache/cache_params.h"

namespace rtusim {

class ConfigReader;

struct L1Params {
  CacheParams cache;              // geometry and replacement (l1.size/assoc/line/policy)
  uint32_t hit_cycles = 2;        // tag + data access
  uint32_t mshrs = 8;             // outstanding line misses
  uint64_t clock_period_ps = 1000;
};

// The l1.* or dcache.* subtree as configured.
struct L1Config {
  L1Params params;            // geometry (params.cache) and timing; clock_period_ps unset
  std::string model = "cpp";  // l1.model: cpp (mem/l1_cache.h) | rtl (the Verilated L1)
  bool enable = true;         // dcache.enable (the node L1 is always on)
};

// Throws KeyError naming `prefix`.hit_cycles / .mshrs / the cache keys.
void validate(const L1Params& p, const std::string& prefix);
// The timing part only (the geometry is checked when read): hit_cycles, mshrs, the clock.
void validate_timing(const L1Params& p, const std::string& prefix);

// Reads the node L1's geometry keys (l1.size/assoc/line/policy/seed), validated.
CacheParams read_node_l1_geometry(ConfigReader& r);
// Reads the node L1's keys (l1.*), validated.
L1Config read_node_l1_config(ConfigReader& r);
// Reads the data cache's keys (dcache.*), validated; enable = dcache.enable.
L1Config read_dcache_config(ConfigReader& r);

}  // namespace rtusim
