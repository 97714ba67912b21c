// The config keys of the cache model, declared in cache_config.cpp (`rtusim keys` lists them):
//   l1.size, l1.assoc, l1.line (bytes), l1.policy, l1.seed      the node L1's geometry
//   dcache.enable (false = lists and triangles straight to DRAM), dcache.size/assoc/line/policy/seed
#pragma once
#include <string>

#include "cache/cache_params.h"
#include "config/config_reader.h"

namespace rtusim {

// Reads `prefix`.size/.assoc/.line/.policy/.seed, `prefix` "l1" or "dcache", and validates them
// together; an error names the key and the `--set` or file line it came from.
CacheParams read_cache_params(ConfigReader& r, const std::string& prefix);

// dcache.enable.
bool read_dcache_enable(ConfigReader& r);

}  // namespace rtusim
