#include "mem/dram/fr_fcfs_dram.h"

#include <algorithm>
#include <bit>

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
    c.head.assign(p.banks, kNil);
    c.tail.assign(p.banks, kNil);
    c.queued.assign((p.banks + 63) / 64, 0);
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
  // In its bank's age order; requests mostly come in arrival order, so the place is found from
  // the back.
  uint32_t& head = c.head[loc.bank];
  uint32_t& tail = c.tail[loc.bank];
  uint32_t before = tail;  // q goes after it (kNil: first)
  while (before != kNil && older(q, c.pool[before])) before = c.pool[before].prev;
  q.prev = before;
  q.next = before == kNil ? head : c.pool[before].next;
  (before == kNil ? head : c.pool[before].next) = e;
  (q.next == kNil ? tail : c.pool[q.next].prev) = e;
  c.queued[loc.bank / 64] |= uint64_t{1} << (loc.bank % 64);
  next_decision_ps_ = std::min(next_decision_ps_, eligible_at(c, q));
}

void FrFcfsDram::advance(uint64_t now_ps, std::vector<DramCompletion>& out) {
  if (next_decision_ps_ > now_ps) return;
  uint64_t next_decision = kNever;  // found by each channel's last scan
  for (Channel& c : channels_) {
    for (;;) {
      // FR-FCFS over the requests that can start now: row hits first, then age. Equal arrival
      // times go by address, so the order in which initiators happened to enqueue them (an
      // artefact of the simulation, not of the hardware) does not matter. A bank's requests can
      // start now if it is ready and they have arrived: in its queue (age order) the first of
      // them with the open row is its best row hit, else the first is its oldest; the choice is
      // the oldest such row hit over the banks, else the oldest such request. With none, the
      // channel's next decision is the earliest time one can start: per bank, its oldest
      // request's (the bank's ready time is the same for all of them).
      Queued* const pool = c.pool.data();
      constexpr uint32_t n = kNil;
      uint32_t hit = n, oldest = n;
      uint64_t later = kNever;
      uint32_t ready_banks = 0;
      for (size_t w = 0; w < c.queued.size(); ++w) {
        for (uint64_t left = c.queued[w]; left; left &= left - 1) {  // the banks with requests
          const size_t k = w * 64 + static_cast<size_t>(std::countr_zero(left));
          uint32_t i = c.head[k];
          const Bank& b = c.banks[k];
          const uint64_t at = std::max(pool[i].req.arrival_ps, b.ready_ps);
          if (at > now_ps) {
            later = std::min(later, at);
            continue;
          }
          ++ready_banks;
          if (oldest == n || older(pool[i], pool[oldest])) oldest = i;
          for (; i != n && pool[i].req.arrival_ps <= now_ps; i = pool[i].next) {
            if (pool[i].loc.row != b.open_row) continue;
            if (hit == n || older(pool[i], pool[hit])) hit = i;
            break;
          }
        }
      }
      const uint32_t best = hit != n ? hit : oldest;
      if (best == n) {  // the channel's next decision: every request left waits
        next_decision = std::min(next_decision, later);
        break;
      }
      const Queued q = pool[best];
      (q.prev == kNil ? c.head[q.loc.bank] : pool[q.prev].next) = q.next;
      if (c.head[q.loc.bank] == kNil)
        c.queued[q.loc.bank / 64] &= ~(uint64_t{1} << (q.loc.bank % 64));
      (q.next == kNil ? c.tail[q.loc.bank] : pool[q.next].prev) = q.prev;
      c.free.push_back(best);

      const uint64_t done = serve(c, c.banks[q.loc.bank], q.loc.row, q.req, eligible_at(c, q));
      out.push_back({q.req.id, done});
      // With no other bank ready, a rescan would only find this bank's next time to start: if
      // it is later, the channel's next decision is known without it.
      if (ready_banks == 1) {
        const uint32_t h = c.head[q.loc.bank];
        const uint64_t at = h == kNil ? kNever : eligible_at(c, pool[h]);
        if (at > now_ps) {
          next_decision = std::min(next_decision, std::min(later, at));
          break;
        }
      }
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
