#include "tier/functional_tier.h"

#include "util/stats.h"

namespace rtusim {

void FunctionalTier::write_stats(Stats& stats) const {
  const FetchCache& c = backend_.caches();
  write_stats(c.counters(), c.data_cache() != nullptr, stats);
}

void FunctionalTier::write_stats(const FetchCache::Counters& counters, bool data_cache_on,
                                 Stats& stats) {
  stats.set("traversal.node_fetches", counters[int(Stream::kNode)].fetches);
  stats.set("traversal.list_fetches", counters[int(Stream::kList)].fetches);
  stats.set("traversal.triangle_fetches", counters[int(Stream::kTriangle)].fetches);
  FetchCache::write_stats(counters, data_cache_on, stats);
}

}  // namespace rtusim
