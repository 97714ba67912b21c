#include "cache/set_assoc_cache.h"

namespace rtusim {

namespace {

SetAssocCache::Variant make_concrete(const CacheParams& p) {
  validate(p, "cache");
  using V = SetAssocCache::Variant;
  if (p.policy == LruPolicy::kName) return V(std::in_place_index<0>, p);
  if (p.policy == TreePlruPolicy::kName) return V(std::in_place_index<1>, p);
  if (p.policy == FifoPolicy::kName) return V(std::in_place_index<2>, p);
  if (p.policy == RandomPolicy::kName) return V(std::in_place_index<3>, p);
  return V(std::in_place_index<4>, p);  // registered with the factory only
}

}  // namespace

SetAssocCache::SetAssocCache(const CacheParams& p) : impl_(make_concrete(p)) {}

SetAssocCache SetAssocCache::through_virtual_policy(const CacheParams& p) {
  return SetAssocCache(Variant(std::in_place_index<4>, p));
}

}  // namespace rtusim
