// The geometry keys of one cache level, declared by the part that owns the level under its own
// prefix (the node L1 and data cache in mem/l1_params.cpp, the L2 in chip/chip_params.cpp):
//   PREFIX.size, PREFIX.assoc (int or "full"), PREFIX.line (bytes), PREFIX.policy, PREFIX.seed
// `rtusim keys` lists every level's keys.
#pragma once
#include <string>

#include "cache/cache_params.h"
#include "config/config_reader.h"
#include "config/param.h"

namespace rtusim {

class CacheLevelKeys {
 public:
  // Declares PREFIX.* with `what` in their descriptions ("node L1") and `defaults`.
  CacheLevelKeys(const std::string& prefix, const std::string& what,
                 const CacheParams& defaults = {});

  // Reads the level's keys and validates them together; an error names the key and the
  // `--set` or file line it came from.
  CacheParams read(ConfigReader& r) const;
  const std::string& prefix() const { return prefix_; }

 private:
  std::string prefix_;
  IntParam size_;
  IntOrWordParam assoc_;
  IntParam line_;
  StringParam policy_;
  IntParam seed_;
};

}  // namespace rtusim
