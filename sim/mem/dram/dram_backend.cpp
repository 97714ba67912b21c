#include "mem/dram/dram_backend.h"

#include <stdexcept>

#include "cache/stream_caches.h"
#include "util/stats.h"

namespace rtusim {

uint64_t DramBackend::read_now(const DramRequest& r) {
  if (next_decision_ps() != kNever) throw std::logic_error("DRAM read_now: requests queued");
  std::vector<DramCompletion> done;
  enqueue(r);
  advance(next_decision_ps(), done);
  if (done.size() != 1) throw std::logic_error("DRAM read_now: read not decided");
  return done[0].done_ps;
}

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
