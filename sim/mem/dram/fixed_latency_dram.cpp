#include "mem/dram/fixed_latency_dram.h"

#include <algorithm>
#include <tuple>

namespace rtusim {

FixedLatencyDram::FixedLatencyDram(const DramParams& p)
    : p_(p), latency_ps_(p.latency_ps()), tBurst_ps_(p.burst_ps()) {
  validate(p, "dram");
  row_ = FastDivider(p.row_bytes);
  channel_ = FastDivider(p.channels);
  burst_ = FastDivider(p.burst_bytes());
  channels_.resize(p.channels);
}

void FixedLatencyDram::enqueue(const DramRequest& r) {
  Channel& c = channel_of(r.addr);
  c.queue.push_back({r, seq_++});
  next_decision_ps_ = std::min(next_decision_ps_, r.arrival_ps);
}

uint64_t FixedLatencyDram::serve(Channel& c, const DramRequest& r) {
  const uint32_t bursts = std::max<uint32_t>(1, burst_.div_up(r.bytes));
  const uint64_t done = std::max(r.arrival_ps + latency_ps_, c.bus_free_ps) + bursts * tBurst_ps_;
  c.bus_free_ps = done;
  count(r);
  return done;
}

void FixedLatencyDram::advance(uint64_t now_ps, std::vector<DramCompletion>& out) {
  if (next_decision_ps_ > now_ps) return;
  next_decision_ps_ = kNever;
  for (Channel& c : channels_) {
    // Arrived requests in (arrival, address, seq) order; the rest wait.
    auto order = [](const Queued& a, const Queued& b) {
      return std::tie(a.req.arrival_ps, a.req.addr, a.seq) <
             std::tie(b.req.arrival_ps, b.req.addr, b.seq);
    };
    std::sort(c.queue.begin(), c.queue.end(), order);
    size_t served = 0;
    for (; served < c.queue.size() && c.queue[served].req.arrival_ps <= now_ps; ++served) {
      const DramRequest& r = c.queue[served].req;
      out.push_back({r.id, serve(c, r)});
    }
    c.queue.erase(c.queue.begin(), c.queue.begin() + static_cast<std::ptrdiff_t>(served));
    if (!c.queue.empty()) next_decision_ps_ = std::min(next_decision_ps_, c.queue.front().req.arrival_ps);
  }
}

void FixedLatencyDram::write_stats(Stats& stats, const std::string& prefix) const {
  write_request_stats(stats, prefix);
}

}  // namespace rtusim
