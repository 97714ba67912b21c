// Declarations of the cache geometry keys, and their reading.
#include "cache/cache_config.h"

#include <algorithm>
#include <cstdint>
#include <optional>

#include "cache/policy/policies.h"
#include "config/param.h"
#include "util/error.h"

namespace rtusim {
namespace {

// The geometry keys of one cache, `prefix`.*.
struct CacheKeys {
  std::string prefix;
  IntParam size;
  IntOrWordParam assoc;
  IntParam line;
  StringParam policy;
  IntParam seed;

  CacheKeys(const std::string& p, const std::string& what, const CacheParams& d = {})
      : prefix(p),
        size(p + ".size", static_cast<int64_t>(d.size_bytes), 4,
             static_cast<int64_t>(kMaxCacheBytes), "bytes", what + " capacity"),
        assoc(p + ".assoc", d.assoc, 1, kMaxCacheWays, "full", "ways",
              what + " ways per set (\"full\": one set, size / line ways)"),
        line(p + ".line", d.line_bytes, 4, 1 << 20, "bytes", what + " line size, a power of two"),
        policy(p + ".policy", d.policy, ReplacementPolicies::names(), "",
               what + " replacement policy"),
        seed(p + ".seed", static_cast<int64_t>(d.seed), 0, INT64_MAX, "",
             what + " seed of the random policy") {}

  CacheParams read(ConfigReader& r) const {
    CacheParams c;
    c.size_bytes = static_cast<uint64_t>(size.read(r));
    const std::optional<int64_t> ways = assoc.read(r);
    c.line_bytes = static_cast<uint32_t>(line.read(r));
    // "full": every line in one set (a size below one line is left to validate()).
    c.assoc = ways ? static_cast<uint32_t>(*ways)
                   : static_cast<uint32_t>(std::max<uint64_t>(1, c.size_bytes / c.line_bytes));
    c.policy = policy.read(r);
    c.seed = static_cast<uint64_t>(seed.read(r));
    try {
      validate(c, prefix);
    } catch (const KeyError& e) {
      r.fail(e);
    }
    return c;
  }
};

const CacheKeys kL1Keys("l1", "node L1");
const CacheKeys kDcacheKeys("dcache", "list/triangle cache");
const BoolParam kDcacheEnable("dcache.enable", false,
                              "list/triangle cache on (false: lists and triangles straight to DRAM)");

}  // namespace

CacheParams read_cache_params(ConfigReader& r, const std::string& prefix) {
  if (prefix == kL1Keys.prefix) return kL1Keys.read(r);
  if (prefix == kDcacheKeys.prefix) return kDcacheKeys.read(r);
  throw std::logic_error("no cache keys under '" + prefix + "'");
}

bool read_dcache_enable(ConfigReader& r) { return kDcacheEnable.read(r); }

}  // namespace rtusim
