#include "tier/functional_tier.h"

#include "util/stats.h"

namespace rtusim {

void FunctionalTier::write_stats(Stats& stats) const {
  const FetchCache& c = backend_.caches();
  stats.set("traversal.node_fetches", c.stream(Stream::kNode).fetches);
  stats.set("traversal.list_fetches", c.stream(Stream::kList).fetches);
  stats.set("traversal.triangle_fetches", c.stream(Stream::kTriangle).fetches);
  c.write_stats(stats);
}

}  // namespace rtusim
