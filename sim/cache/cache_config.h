// Config keys of the cache model, read through ConfigReader (typed, ranged, errors name the key).
//   l1.size, l1.assoc, l1.line (bytes), l1.policy, l1.seed      the node L1
//   dcache.enable (false = lists and triangles straight to DRAM), dcache.size/assoc/line/policy/seed
#pragma once
#include <string>

#include "cache/cache_params.h"
#include "cache/stream_caches.h"
#include "config/config_reader.h"

namespace rtusim {

// Reads `prefix`.size/.assoc/.line/.policy/.seed (absent keys take `defaults`) and validates
// them together; a combination error names the keys and the config file.
CacheParams read_cache_params(ConfigReader& r, const std::string& prefix,
                              const CacheParams& defaults = {});

// The node L1 (l1.*) and the data cache (dcache.*; on only when dcache.enable = true).
FetchCacheParams read_fetch_cache_params(ConfigReader& r);

}  // namespace rtusim
