#include "cache/set_assoc_cache.h"

namespace rtusim {

namespace {

SetAssocCache::Variant make_concrete(const CacheParams& p) {
  validate(p, "cache");
  return ReplacementPolicies::dispatch(p.policy, [&]<class Policy>() {
    return SetAssocCache::Variant(std::in_place_type<BasicSetAssocCache<Policy>>, p);
  });
}

}  // namespace

SetAssocCache::SetAssocCache(const CacheParams& p) : impl_(make_concrete(p)) {}

SetAssocCache SetAssocCache::through_virtual_policy(const CacheParams& p) {
  return SetAssocCache(Variant(std::in_place_type<BasicSetAssocCache<DynamicPolicy>>, p));
}

}  // namespace rtusim
