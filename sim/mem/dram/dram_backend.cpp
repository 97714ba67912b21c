#include "mem/dram/dram_backend.h"

#include "cache/fetch_cache.h"
#include "util/stat_decl.h"
#include "util/stats.h"

namespace rtusim {
namespace {
// Stats keys of every DRAM model (its bytes are dram.bytes.*).
const StatDecl kRequests("dram.requests", StatKind::kCounter, "requests",
                         "reads DRAM served");
}  // namespace


void DramBackend::write_request_stats(Stats& stats, const std::string& prefix) const {
  stats.set(prefix + ".requests", requests_);
  uint64_t total = 0;
  for (int s = 0; s < 3; ++s) {
    stats.set(prefix + ".bytes." + stream_stats_name(static_cast<Stream>(s)), bytes_[s]);
    total += bytes_[s];
  }
  stats.set(prefix + ".bytes.total", total);
}

}  // namespace rtusim
