#include "mem/dram/fr_fcfs_dram.h"

#include <algorithm>

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
  for (Channel& c : channels_) {
    c.banks.resize(p.banks);
    c.waiting.resize(p.banks, 0);
    c.seen.resize(p.banks, 0);
  }
}

void FrFcfsDram::enqueue(const DramRequest& r) {
  const Location loc = locate(r.addr);
  Channel& c = channels_[loc.channel];
  uint32_t e;
  if (c.free.empty()) {
    e = static_cast<uint32_t>(c.pool.size());
    c.pool.emplace_back();
  } else {
    e = c.free.back();
    c.free.pop_back();
  }
  Queued& q = c.pool[e];
  q.req = r;
  q.loc = loc;
  q.seq = seq_++;
  // In age order; requests mostly come in arrival order, so the place is found from the back.
  uint32_t before = c.tail;  // q goes after it (kNil: first)
  while (before != kNil && older(q, c.pool[before])) before = c.pool[before].prev;
  q.prev = before;
  q.next = before == kNil ? c.head : c.pool[before].next;
  (before == kNil ? c.head : c.pool[before].next) = e;
  (q.next == kNil ? c.tail : c.pool[q.next].prev) = e;
  if (c.waiting[loc.bank]++ == 0) ++c.banks_waiting;
  next_decision_ps_ = std::min(next_decision_ps_, eligible_at(c, q));
}

void FrFcfsDram::advance(uint64_t now_ps, std::vector<DramCompletion>& out) {
  if (next_decision_ps_ > now_ps) return;
  uint64_t next_decision = kNever;  // found by each channel's last scan
  for (Channel& c : channels_) {
    for (;;) {
      // FR-FCFS over the requests that can start now: row hits first, then age. Equal arrival
      // times go by address, so the order in which initiators happened to enqueue them (an
      // artefact of the simulation, not of the hardware) does not matter. The queue is in age
      // order: the first eligible row hit is the choice, else the first eligible request.
      // With none eligible, the channel's next decision is the earliest time one becomes so:
      // per bank, that of its oldest request (the bank's ready time is the same for all), so
      // the scan stops once it has met every bank with requests, or a request arriving after
      // the earliest time found (all after it arrive later still).
      ++scan_;
      const Queued* const pool = c.pool.data();
      constexpr uint32_t n = kNil;
      uint32_t best = n, oldest = n;
      uint64_t later = kNever;
      uint32_t banks_met = 0;
      for (uint32_t i = c.head; i != kNil; i = pool[i].next) {
        const Queued& q = pool[i];
        const Bank& b = c.banks[q.loc.bank];
        const uint64_t at = std::max(q.req.arrival_ps, b.ready_ps);
        if (at <= now_ps) {
          if (b.open_row == q.loc.row) {
            best = i;
            break;
          }
          if (oldest == n) oldest = i;
          continue;
        }
        if (oldest != n) {  // one is eligible: only an eligible row hit can still win
          if (q.req.arrival_ps > now_ps) break;
          continue;
        }
        later = std::min(later, at);
        if (q.req.arrival_ps >= later) break;
        if (c.seen[q.loc.bank] != scan_) {
          c.seen[q.loc.bank] = scan_;
          if (++banks_met == c.banks_waiting) break;
        }
      }
      if (best == n) best = oldest;
      if (best == n) {  // the channel's next decision: every request left waits
        next_decision = std::min(next_decision, later);
        break;
      }
      const Queued q = pool[best];
      (q.prev == kNil ? c.head : c.pool[q.prev].next) = q.next;
      (q.next == kNil ? c.tail : c.pool[q.next].prev) = q.prev;
      c.free.push_back(best);
      if (--c.waiting[q.loc.bank] == 0) --c.banks_waiting;

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
