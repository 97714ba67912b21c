#include "cache/replacement_policy.h"

#include <algorithm>

#include "cache/policy/fifo_policy.h"
#include "cache/policy/lru_policy.h"
#include "cache/policy/random_policy.h"
#include "cache/policy/tree_plru_policy.h"
#include "util/error.h"

namespace rtusim {

const std::vector<std::string>& known_replacement_policies() {
  static const std::vector<std::string> names = {LruPolicy::kName, TreePlruPolicy::kName,
                                                 FifoPolicy::kName, RandomPolicy::kName};
  return names;
}

bool is_known_replacement_policy(std::string_view name) {
  const auto& names = known_replacement_policies();
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::string known_replacement_policies_text() {
  std::string text;
  for (const auto& n : known_replacement_policies()) text += (text.empty() ? "" : ", ") + n;
  return text;
}

std::unique_ptr<ReplacementPolicy> make_replacement_policy(std::string_view name, uint32_t sets,
                                                           uint32_t ways, uint64_t seed) {
  if (name == LruPolicy::kName) return std::make_unique<LruPolicy>(sets, ways, seed);
  if (name == TreePlruPolicy::kName) return std::make_unique<TreePlruPolicy>(sets, ways, seed);
  if (name == FifoPolicy::kName) return std::make_unique<FifoPolicy>(sets, ways, seed);
  if (name == RandomPolicy::kName) return std::make_unique<RandomPolicy>(sets, ways, seed);
  throw InputError("unknown cache replacement policy \"" + std::string(name) +
                   "\" (known: " + known_replacement_policies_text() + ")");
}

}  // namespace rtusim
