#include "cache/fetch_cache.h"

#include "util/stat_decl.h"
#include "util/stats.h"

namespace rtusim {
namespace {
// Stats keys of the cache levels and the fetch streams (written here, and by every tier).
const StatDecl kLevelAccesses("<level>.accesses", StatKind::kCounter, "lines",
                              "line accesses of the level (l1: node L1, dcache: list/triangle "
                              "cache, l2: shared L2; a fetch across a line boundary is two)");
const StatDecl kLevelHits("<level>.hits", StatKind::kCounter, "lines",
                          "line accesses of the level that hit");
const StatDecl kLevelMisses("<level>.misses", StatKind::kCounter, "lines",
                            "line accesses of the level that missed (merged misses included)");
const StatDecl kStreamFetches("fetch.<stream>.fetches", StatKind::kCounter, "fetches",
                              "fetches of the stream by the traversal");
const StatDecl kStreamAccesses("fetch.<stream>.accesses", StatKind::kCounter, "lines",
                               "line accesses of the stream at its first cache (DRAM bursts when "
                               "it goes straight past)");
const StatDecl kStreamHits("fetch.<stream>.hits", StatKind::kCounter, "lines",
                           "the stream's line accesses that hit");
const StatDecl kStreamMisses("fetch.<stream>.misses", StatKind::kCounter, "lines",
                             "the stream's line accesses that missed");
const StatDecl kDramStreamBytes("dram.bytes.<stream>", StatKind::kCounter, "bytes",
                                "bytes of the stream read from DRAM");
const StatDecl kDramBytes("dram.bytes.total", StatKind::kCounter, "bytes",
                          "bytes read from DRAM, all streams");

SetAssocCache make_cache(const CacheParams& p, const std::string& key_prefix) {
  validate(p, key_prefix);
  return SetAssocCache(p);
}

}  // namespace

FetchCache::FetchCache(const FetchCacheParams& p)
    : node_l1_(make_cache(p.node_l1, "l1")), burst_bytes_(p.dram_burst_bytes) {
  if (p.data_cache) data_cache_.emplace(make_cache(*p.data_cache, "dcache"));
}

const char* stream_stats_name(Stream s) {
  switch (s) {
    case Stream::kNode: return "nodes";
    case Stream::kList: return "lists";
    case Stream::kTriangle: return "triangles";
  }
  return "?";
}

void FetchCache::write_stats(const Counters& counters, bool data_cache_on, Stats& stats) {
  const StreamCounters& n = counters[0];
  stats.set("l1.accesses", n.accesses);
  stats.set("l1.hits", n.hits);
  stats.set("l1.misses", n.misses);
  if (data_cache_on) {
    const StreamCounters &l = counters[1], &t = counters[2];
    stats.set("dcache.accesses", l.accesses + t.accesses);
    stats.set("dcache.hits", l.hits + t.hits);
    stats.set("dcache.misses", l.misses + t.misses);
  }
  for (const Stream s : {Stream::kNode, Stream::kList, Stream::kTriangle}) {
    const StreamCounters& c = counters[static_cast<int>(s)];
    const std::string stem = std::string("fetch.") + stream_stats_name(s);
    stats.set(stem + ".fetches", c.fetches);
    stats.set(stem + ".accesses", c.accesses);
    stats.set(stem + ".hits", c.hits);
    stats.set(stem + ".misses", c.misses);
    stats.set(std::string("dram.bytes.") + stream_stats_name(s), c.dram_bytes);
  }
  stats.set("dram.bytes.total", dram_bytes_total(counters));
}

}  // namespace rtusim
