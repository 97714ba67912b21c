// The functional tier's stats, and its keys (functional.*).
#include "tier/functional_tier.h"

#include "config/param.h"
#include "util/stats.h"

namespace rtusim {
namespace {
const FunctionalParams kFunctional;
const IntParam kRaysInFlight("functional.rays_in_flight", kFunctional.rays_in_flight, 1, 1 << 16,
                             "rays",
                             "rays in traversal at once, one step each in turn (1: each ray to "
                             "the end in turn; more: the cycle tier's interleaving, no time)");
const BoolParam kTimed("functional.timed", kFunctional.timed,
                       "rays in flight take turns by an approximate model of the cycle tier's "
                       "timing (its sim.*, isect.*, l1.*, dcache.*, dram.* keys) and "
                       "estimate.cycles is reported; false: strict round-robin, no time");
const IntParam kTimedSegments("functional.timed_segments", kFunctional.timed_segments, 1, 4096,
                              "runs",
                              "timed mode: a batch is cut into up to this many runs of rays, "
                              "each timed by its own model on any thread, warmed by the rays "
                              "before it (same figures for any thread count; 1: one model)");
const IntParam kTimedWarmup("functional.timed_warmup_rays", kFunctional.timed_warmup_rays, 1,
                            1 << 20, "rays",
                            "timed mode in runs: rays before each run timed unmeasured to warm "
                            "its model and caches (at least 4 x functional.rays_in_flight; a "
                            "run has at least 8 times as many)");
}  // namespace

FunctionalParams read_functional_params(ConfigReader& r) {
  FunctionalParams p;
  p.rays_in_flight = static_cast<int>(kRaysInFlight.read(r));
  p.timed = kTimed.read(r);
  p.timed_segments = static_cast<int>(kTimedSegments.read(r));
  p.timed_warmup_rays = static_cast<int>(kTimedWarmup.read(r));
  return p;
}

void FunctionalTier::write_stats(Stats& stats) const {
  const FetchCache& c = backend_.caches();
  write_stats(c.counters(), c.data_cache() != nullptr, stats);
  if (backend_.rays_in_flight() > 1 || backend_.timed())
    stats.set("functional.rays_in_flight", backend_.rays_in_flight());
  if (backend_.timed()) {
    stats.set("functional.timed", true);
    if (backend_.timed()->segments() > 1)
      stats.set("functional.timed_segments", backend_.timed()->segments());
    backend_.timed()->write_stats(stats);
  }
}

void FunctionalTier::write_stats(const FetchCache::Counters& counters, bool data_cache_on,
                                 Stats& stats) {
  stats.set("traversal.node_fetches", counters[int(Stream::kNode)].fetches);
  stats.set("traversal.list_fetches", counters[int(Stream::kList)].fetches);
  stats.set("traversal.triangle_fetches", counters[int(Stream::kTriangle)].fetches);
  FetchCache::write_stats(counters, data_cache_on, stats);
}

}  // namespace rtusim
