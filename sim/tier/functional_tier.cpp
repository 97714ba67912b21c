// The functional tier's stats, and its keys (functional.*).
#include "tier/functional_tier.h"

#include "config/param.h"
#include "util/stat_decl.h"
#include "util/stats.h"

namespace rtusim {
namespace {
// Stats keys of the functional tier and its chip.
const StatDecl kNodeFetches("traversal.node_fetches", StatKind::kCounter, "fetches",
                            "node fetches (traversal steps)");
const StatDecl kListFetches("traversal.list_fetches", StatKind::kCounter, "fetches",
                            "leaf primitive-list fetches");
const StatDecl kTriangleFetches("traversal.triangle_fetches", StatKind::kCounter, "fetches",
                                "triangle fetches");
const StatDecl kRaysInFlightStat("functional.rays_in_flight", StatKind::kProperty, "rays",
                                 "the interleaved mode's rays in flight");
const StatDecl kTimedStat("functional.timed", StatKind::kProperty, "",
                          "the timed mode was on");
const StatDecl kTimedSegmentsStat("functional.timed_segments", StatKind::kProperty, "runs",
                                  "the timed mode's runs");
const StatDecl kChipUnits("chip.units", StatKind::kProperty, "units",
                          "traversal units of the chip (written when several, or with an L2)");
const StatDecl kL2BytesIn("l2.bytes.in", StatKind::kCounter, "bytes",
                          "bytes the units' caches read from the L2 (lines they missed, bursts "
                          "past them)");
const StatDecl kL2StreamBytesIn("l2.bytes.in.<stream>", StatKind::kCounter, "bytes",
                                "l2.bytes.in of the stream");
const StatDecl kL2MissRate("l2.miss_rate", StatKind::kRatio, "",
                           "l2.misses / l2.accesses");

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

FunctionalTier::FunctionalTier(const MemoryImage& image, const TierConfig& config) {
  if (!config.chip.single_unit()) {
    chip_ = std::make_unique<ChipFunctionalBackend>(image, config.caches, config.chip,
                                                    config.width, config.pixels);
    return;
  }
  backend_ = std::make_unique<FunctionalBackend>(
      image, config.caches, config.pixels, config.functional.rays_in_flight,
      config.functional.timed ? &config.cycle : nullptr, config.functional.timed_segments,
      config.functional.timed_warmup_rays);
}

void FunctionalTier::write_stats(Stats& stats) const {
  if (chip_) return write_chip_stats(chip_->chip(), chip_->chip().l2_counts(), stats);
  const FunctionalBackend& b = *backend_;
  const FetchCache& c = b.caches();
  write_stats(c.counters(), c.data_cache() != nullptr, stats);
  if (b.rays_in_flight() > 1 || b.timed())
    stats.set("functional.rays_in_flight", b.rays_in_flight());
  if (b.timed()) {
    stats.set("functional.timed", true);
    if (b.timed()->segments() > 1) stats.set("functional.timed_segments", b.timed()->segments());
    b.timed()->write_stats(stats);
  }
}

void FunctionalTier::write_chip_stats(const ChipCaches& chip, const ChipL2Counts& l2,
                                      Stats& stats) {
  const bool data_cache_on = chip.unit(0).data_cache() != nullptr;
  // The units' sums under the one-unit keys; with an L2 their DRAM bytes are the L2's input.
  write_stats(chip.total_counters(), data_cache_on, stats);
  stats.set("chip.units", chip.units());
  for (uint32_t u = 0; u < chip.units(); ++u) {
    const std::string prefix = "units." + std::to_string(u) + ".";
    Stats unit;
    write_stats(chip.unit(u).counters(), data_cache_on, unit);
    for (const auto& [key, value] : unit.values())
      if (!chip.has_l2() || !key.starts_with("dram.")) stats.set(prefix + key, value);
    stats.set(prefix + "rays.total", chip.rays(u));
    if (chip.has_l2()) {
      const L2Counters& c = l2.units[u];
      stats.set(prefix + "l2.accesses", c.accesses);
      stats.set(prefix + "l2.hits", c.hits);
      stats.set(prefix + "l2.misses", c.misses);
      stats.set(prefix + "l2.bytes.in", c.bytes_in);
      stats.set(prefix + "dram.bytes.total", c.dram_bytes);
    }
  }
  if (!chip.has_l2()) return;
  // The L2: its input per stream, and DRAM's bytes are what it read.
  L2Counters all;
  for (int s = 0; s < FetchCache::kStreams; ++s) {
    const L2Counters& c = l2.streams[s];
    all.accesses += c.accesses;
    all.hits += c.hits;
    all.misses += c.misses;
    all.bytes_in += c.bytes_in;
    all.dram_bytes += c.dram_bytes;
    const std::string stem = stream_stats_name(static_cast<Stream>(s));
    stats.set("l2.bytes.in." + stem, c.bytes_in);
    stats.set("dram.bytes." + stem, c.dram_bytes);
  }
  stats.set("dram.bytes.total", all.dram_bytes);
  stats.set("l2.accesses", all.accesses);
  stats.set("l2.hits", all.hits);
  stats.set("l2.misses", all.misses);
  stats.set("l2.bytes.in", all.bytes_in);
  stats.set("l2.miss_rate", all.accesses ? double(all.misses) / double(all.accesses) : 0.0);
}

void FunctionalTier::write_stats(const FetchCache::Counters& counters, bool data_cache_on,
                                 Stats& stats) {
  stats.set("traversal.node_fetches", counters[int(Stream::kNode)].fetches);
  stats.set("traversal.list_fetches", counters[int(Stream::kList)].fetches);
  stats.set("traversal.triangle_fetches", counters[int(Stream::kTriangle)].fetches);
  FetchCache::write_stats(counters, data_cache_on, stats);
}

}  // namespace rtusim
