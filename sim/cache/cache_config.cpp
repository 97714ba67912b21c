// The geometry keys of a cache level, and their reading.
#include "cache/cache_config.h"

#include <algorithm>
#include <cstdint>
#include <optional>

#include "cache/policy/policies.h"
#include "util/error.h"

namespace rtusim {
CacheLevelKeys::CacheLevelKeys(const std::string& prefix, const std::string& what,
                               const CacheParams& d)
    : prefix_(prefix),
      size_(prefix + ".size", static_cast<int64_t>(d.size_bytes), 4,
            static_cast<int64_t>(kMaxCacheBytes), "bytes", what + " capacity"),
      assoc_(prefix + ".assoc", d.assoc, 1, kMaxCacheWays, "full", "ways",
             what + " ways per set (\"full\": one set, size / line ways)"),
      line_(prefix + ".line", d.line_bytes, 4, 1 << 20, "bytes",
            what + " line size, a power of two"),
      policy_(prefix + ".policy", d.policy, ReplacementPolicies::names(), "",
              what + " replacement policy"),
      seed_(prefix + ".seed", static_cast<int64_t>(d.seed), 0, INT64_MAX, "",
            what + " seed of the random policy") {}

CacheParams CacheLevelKeys::read(ConfigReader& r) const {
  CacheParams c;
  c.size_bytes = static_cast<uint64_t>(size_.read(r));
  const std::optional<int64_t> ways = assoc_.read(r);
  c.line_bytes = static_cast<uint32_t>(line_.read(r));
  // "full": every line in one set (a size below one line is left to validate()).
  c.assoc = ways ? static_cast<uint32_t>(*ways)
                 : static_cast<uint32_t>(std::max<uint64_t>(1, c.size_bytes / c.line_bytes));
  c.policy = policy_.read(r);
  c.seed = static_cast<uint64_t>(seed_.read(r));
  try {
    validate(c, prefix_);
  } catch (const KeyError& e) {
    r.fail(e);
  }
  return c;
}

}  // namespace rtusim
