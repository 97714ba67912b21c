#include "cache/cache_params.h"

#include <bit>

#include "cache/replacement_policy.h"
#include "util/error.h"

namespace rtusim {

void validate(const CacheParams& p, const std::string& key_prefix) {
  const std::string size_key = key_prefix + ".size", assoc_key = key_prefix + ".assoc",
                    line_key = key_prefix + ".line", policy_key = key_prefix + ".policy";
  // Every check names its key first, then the other keys it involves.
  auto fail = [&](const std::string& key, const std::string& what) {
    throw KeyError({key, size_key, assoc_key, line_key, policy_key}, what);
  };
  if (p.line_bytes < 4 || !std::has_single_bit(p.line_bytes))
    fail(line_key, std::to_string(p.line_bytes) + " must be a power of two >= 4");
  if (p.assoc < 1) fail(assoc_key, "0 must be at least 1");
  if (p.size_bytes > kMaxCacheBytes)
    fail(size_key, std::to_string(p.size_bytes) + " exceeds the limit of " +
                       std::to_string(kMaxCacheBytes) + " bytes");
  if (p.assoc > kMaxCacheWays)  // "full" over a large cache of small lines
    fail(assoc_key, std::to_string(p.assoc) + " ways (" + size_key + " / " + line_key +
                        ") exceed the limit of " + std::to_string(kMaxCacheWays));
  const uint64_t set_bytes = uint64_t{p.line_bytes} * p.assoc;
  const std::string set_bytes_text =
      line_key + " x " + assoc_key + " (" + std::to_string(set_bytes) + ")";
  if (p.size_bytes < set_bytes)
    fail(size_key, std::to_string(p.size_bytes) + " is smaller than " + set_bytes_text);
  if (p.size_bytes % set_bytes != 0)
    fail(size_key, std::to_string(p.size_bytes) + " is not a multiple of " + set_bytes_text);
  if (!std::has_single_bit(p.sets()))
    fail(size_key, std::to_string(p.size_bytes) + " gives " + std::to_string(p.sets()) +
                       " sets (" + size_key + " / (" + line_key + " x " + assoc_key +
                       ")); the set count must be a power of two");
  if (!is_known_replacement_policy(p.policy))
    fail(policy_key, "unknown policy \"" + p.policy + "\" (known: " +
                         known_replacement_policies_text() + ")");
  if (const std::string why = replacement_policy_ways_problem(p.policy, p.assoc); !why.empty())
    fail(assoc_key, std::to_string(p.assoc) + " " + why + " for " + policy_key + " = \"" +
                        p.policy + "\"");
}

}  // namespace rtusim
