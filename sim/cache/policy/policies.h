// The registry of replacement policies (l1.policy, dcache.policy): one entry per policy, in the
// order errors and `rtusim keys` list them. A new policy is a file in policy/ (a final
// ReplacementPolicy with kName and a (sets, ways, seed) constructor) plus its entry here.
#pragma once
#include "cache/policy/fifo_policy.h"
#include "cache/policy/lru_policy.h"
#include "cache/policy/random_policy.h"
#include "cache/policy/tree_plru_policy.h"
#include "util/type_registry.h"

namespace rtusim {

using ReplacementPolicies = TypeRegistry<LruPolicy, TreePlruPolicy, FifoPolicy, RandomPolicy>;

}  // namespace rtusim
