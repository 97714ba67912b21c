#include "cache/cache_config.h"

#include "cache/replacement_policy.h"
#include "util/error.h"

namespace rtusim {

CacheParams read_cache_params(ConfigReader& r, const std::string& prefix,
                              const CacheParams& defaults) {
  CacheParams p;
  p.size_bytes = static_cast<uint64_t>(r.get_int(prefix + ".size",
                                                 static_cast<int64_t>(defaults.size_bytes), 4,
                                                 static_cast<int64_t>(kMaxCacheBytes)));
  p.assoc = static_cast<uint32_t>(r.get_int(prefix + ".assoc", defaults.assoc, 1, 1 << 24));
  p.line_bytes = static_cast<uint32_t>(r.get_int(prefix + ".line", defaults.line_bytes, 4, 1 << 20));
  p.policy = r.get_string(prefix + ".policy", defaults.policy, known_replacement_policies());
  p.seed = static_cast<uint64_t>(
      r.get_int(prefix + ".seed", static_cast<int64_t>(defaults.seed), 0, INT64_MAX));
  try {
    validate(p, prefix);
  } catch (const InputError& e) {
    throw InputError(r.origin() + ": " + e.what());
  }
  return p;
}

FetchCacheParams read_fetch_cache_params(ConfigReader& r) {
  FetchCacheParams p;
  p.node_l1 = read_cache_params(r, "l1");
  const bool dcache_on = r.get_bool("dcache.enable", false);
  const CacheParams dcache = read_cache_params(r, "dcache");
  if (dcache_on) p.data_cache = dcache;
  return p;
}

}  // namespace rtusim
