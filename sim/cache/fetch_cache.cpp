#include "cache/fetch_cache.h"

#include "util/stats.h"

namespace rtusim {

namespace {

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
