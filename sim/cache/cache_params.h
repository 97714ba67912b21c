// Parameters of one set-associative cache, and their validation (errors name the config key).
#pragma once
#include <cstdint>
#include <string>

namespace rtusim {

struct CacheParams {
  uint64_t size_bytes = 8192;  // total data capacity
  uint32_t assoc = 4;          // ways per set; size / line = fully associative
  uint32_t line_bytes = 64;    // line (block) size, a power of two >= 4
  std::string policy = "lru";  // replacement policy: see replacement_policy.h
  uint64_t seed = 1;           // seed of the "random" policy

  uint64_t lines() const { return size_bytes / line_bytes; }
  uint64_t sets() const { return size_bytes / (uint64_t{line_bytes} * assoc); }
};

// The largest cache accepted (the tag array is 8 bytes per line).
inline constexpr uint64_t kMaxCacheBytes = uint64_t{1} << 30;
// The most ways a set may have (a set's tags are searched one by one), "full" included.
inline constexpr uint32_t kMaxCacheWays = uint32_t{1} << 24;

// Throws KeyError (an InputError) with a one-line message naming the offending key, `key_prefix` + ".size",
// ".assoc", ".line", ".policy" (e.g. "l1.size: 8000 is not a multiple of l1.line x l1.assoc (256)").
void validate(const CacheParams& p, const std::string& key_prefix);

}  // namespace rtusim
