#include "mem/dram/fr_fcfs_dram.h"

#include <algorithm>
#include <tuple>

#include "util/stats.h"

namespace rtusim {

FrFcfsDram::FrFcfsDram(const DramParams& p)
    : p_(p), tRCD_(p.tRCD_ps()), tRP_(p.tRP_ps()), tCL_(p.tCL_ps()), tBurst_(p.burst_ps()) {
  validate(p, "dram");
  row_ = FastDivider(p.row_bytes);
  channel_ = FastDivider(p.channels);
  bank_ = FastDivider(p.banks);
  burst_ = FastDivider(p.burst_bytes());
  channels_.resize(p.channels);
  for (Channel& c : channels_) c.banks.resize(p.banks);
}

void FrFcfsDram::enqueue(const DramRequest& r) {
  const Location loc = locate(r.addr);
  Channel& c = channels_[loc.channel];
  c.queue.push_back({r, loc, seq_++});
  next_decision_ps_ = std::min(next_decision_ps_, eligible_at(c, c.queue.back()));
}

void FrFcfsDram::advance(uint64_t now_ps, std::vector<DramCompletion>& out) {
  if (next_decision_ps_ > now_ps) return;
  uint64_t next_decision = kNever;  // found by each channel's last scan
  for (Channel& c : channels_) {
    for (;;) {
      // FR-FCFS over the requests that can start now: row hits first, then age. Equal arrival
      // times go by address, so the order in which initiators happened to enqueue them (an
      // artefact of the simulation, not of the hardware) does not matter.
      auto age = [](const Queued& x) { return std::tie(x.req.arrival_ps, x.req.addr, x.seq); };
      int best = -1;
      bool best_hit = false;
      const Queued* best_q = nullptr;  // c.queue[best]
      uint64_t later = kNever;  // the earliest time a request not eligible now becomes so
      for (size_t i = 0; i < c.queue.size(); ++i) {
        const Queued& q = c.queue[i];
        const uint64_t at = eligible_at(c, q);
        if (at > now_ps) {
          later = std::min(later, at);
          continue;
        }
        const bool hit = c.banks[q.loc.bank].open_row == q.loc.row;
        if (best < 0 || (hit && !best_hit) || (hit == best_hit && age(q) < age(*best_q))) {
          best = static_cast<int>(i);
          best_hit = hit;
          best_q = &q;
        }
      }
      if (best < 0) {  // the channel's next decision: every request left waits
        next_decision = std::min(next_decision, later);
        break;
      }
      const Queued q = c.queue[best];
      c.queue[best] = c.queue.back();
      c.queue.pop_back();

      const uint64_t done = serve(c, c.banks[q.loc.bank], q.loc.row, q.req, eligible_at(c, q));
      out.push_back({q.req.id, done});
    }
  }
  next_decision_ps_ = next_decision;
}

void FrFcfsDram::write_stats(Stats& stats, const std::string& prefix) const {
  const uint64_t rows = row_hits_ + row_misses_ + row_conflicts_;
  write_request_stats(stats, prefix);
  stats.set(prefix + ".row_hits", row_hits_);
  stats.set(prefix + ".row_misses", row_misses_);
  stats.set(prefix + ".row_conflicts", row_conflicts_);
  stats.set(prefix + ".row_hit_rate", rows ? double(row_hits_) / double(rows) : 0.0);
}

}  // namespace rtusim
