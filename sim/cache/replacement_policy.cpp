#include "cache/replacement_policy.h"

#include "cache/policy/policies.h"
#include "util/error.h"

namespace rtusim {

const std::vector<std::string>& known_replacement_policies() {
  static const std::vector<std::string> names = ReplacementPolicies::names();
  return names;
}

bool is_known_replacement_policy(std::string_view name) {
  return ReplacementPolicies::contains(name);
}

std::string known_replacement_policies_text() { return ReplacementPolicies::names_text(); }

std::string replacement_policy_ways_problem(std::string_view name, uint32_t ways) {
  return ReplacementPolicies::dispatch(name, [&]<class P>() -> std::string {
    if constexpr (requires { P::ways_problem(ways); })
      return P::ways_problem(ways);
    else
      return {};
  });
}

std::unique_ptr<ReplacementPolicy> make_replacement_policy(std::string_view name, uint32_t sets,
                                                           uint32_t ways, uint64_t seed) {
  if (!ReplacementPolicies::contains(name))
    throw InputError("unknown cache replacement policy \"" + std::string(name) +
                     "\" (known: " + known_replacement_policies_text() + ")");
  return ReplacementPolicies::dispatch(name, [&]<class P>() -> std::unique_ptr<ReplacementPolicy> {
    return std::make_unique<P>(sets, ways, seed);
  });
}

}  // namespace rtusim
