#include "cache/stream_caches.h"

#include "util/stats.h"

namespace rtusim {

namespace {

SetAssocCache make_cache(const CacheParams& p, const std::string& key_prefix) {
  validate(p, key_prefix);
  return SetAssocCache(p);
}

}  // namespace

FetchCache::FetchCache(const FetchCacheParams& p) : node_l1_(make_cache(p.node_l1, "l1")) {
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

void FetchCache::write_stats(Stats& stats) const {
  stats.set("l1.accesses", node_l1_.accesses());
  stats.set("l1.hits", node_l1_.hits());
  stats.set("l1.misses", node_l1_.misses());
  if (data_cache_) {
    stats.set("dcache.accesses", data_cache_->accesses());
    stats.set("dcache.hits", data_cache_->hits());
    stats.set("dcache.misses", data_cache_->misses());
  }
  for (const Stream s : {Stream::kNode, Stream::kList, Stream::kTriangle}) {
    const StreamCounters& c = stream(s);
    const std::string stem = std::string("fetch.") + stream_stats_name(s);
    stats.set(stem + ".fetches", c.fetches);
    stats.set(stem + ".accesses", c.accesses);
    stats.set(stem + ".hits", c.hits);
    stats.set(stem + ".misses", c.misses);
    stats.set(std::string("dram.bytes.") + stream_stats_name(s), c.dram_bytes);
  }
  stats.set("dram.bytes.total", dram_bytes_total());
}

}  // namespace rtusim
