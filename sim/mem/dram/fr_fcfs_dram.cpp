#include "mem/dram/fr_fcfs_dram.h"

#include <algorithm>
#include <bit>

#include "util/stat_decl.h"
#include "util/stats.h"

namespace rtusim {
namespace {
// Stats keys of the FR-FCFS DRAM model.
const StatDecl kRowHits("dram.row_hits", StatKind::kCounter, "requests",
                        "requests to the open row of their bank");
const StatDecl kRowMisses("dram.row_misses", StatKind::kCounter, "requests",
                          "requests to a bank with no open row");
const StatDecl kRowConflicts("dram.row_conflicts", StatKind::kCounter, "requests",
                             "requests that closed another open row");
const StatDecl kRowHitRate("dram.row_hit_rate", StatKind::kRatio, "",
                           "row hits / requests");
}  // namespace


FrFcfsDram::FrFcfsDram(const DramParams& p)
    : p_(p), tRCD_ps_(p.tRCD_ps()), tRP_ps_(p.tRP_ps()), tCL_ps_(p.tCL_ps()), tBurst_ps_(p.burst_ps()) {
  validate(p, "dram");
  row_ = FastDivider(p.row_bytes);
  channel_ = FastDivider(p.channels);
  bank_ = FastDivider(p.banks);
  burst_ = FastDivider(p.burst_bytes());
  channels_.resize(p.channels);
  for (Channel& c : channels_) {
    c.banks.resize(p.banks);
    c.queued.assign((p.banks + 63) / 64, 0);
    c.ready.assign((p.banks + 63) / 64, 0);
  }
}

void FrFcfsDram::enqueue(const DramRequest& r) {
  const Location loc = locate(r.addr);
  Channel& c = channels_[loc.channel];
  uint32_t e = c.free;
  if (e == kNil) {
    e = static_cast<uint32_t>(c.pool.size());
    c.pool.emplace_back();
  } else {
    c.free = c.pool[e].next;
  }
  Queued& q = c.pool[e];
  q.req = r;
  q.row = loc.row;
  q.seq = seq_++;
  // In its bank's age order; requests mostly come in arrival order, so the place is found from
  // the back.
  Bank& b = c.banks[loc.bank];
  uint32_t before = b.tail;  // q goes after it (kNil: first)
  while (before != kNil && older(q, c.pool[before])) before = c.pool[before].prev;
  q.prev = before;
  q.next = before == kNil ? b.head : c.pool[before].next;
  (before == kNil ? b.head : c.pool[before].next) = e;
  (q.next == kNil ? b.tail : c.pool[q.next].prev) = e;
  // The bank's oldest request: the next decision is never later than its start (a later request
  // starts no earlier).
  if (before == kNil) {
    c.queued[loc.bank / 64] |= uint64_t{1} << (loc.bank % 64);
    b.start_ps = start_at(r, b);
    next_decision_ps_ = std::min(next_decision_ps_, b.start_ps);
  }
  // Its first request for the open row (a request placed last comes after any).
  if (loc.row == b.open_row &&
      (b.hit == kNil || (q.next != kNil && older(q, c.pool[b.hit])))) {
    b.hit = e;
    b.hit_arrival_ps = r.arrival_ps;
  }
}

void FrFcfsDram::advance(uint64_t now_ps, std::vector<DramCompletion>& out) {
  if (next_decision_ps_ > now_ps) return;
  uint64_t next_decision = kNever;
  for (Channel& c : channels_) {
    // The banks that can start a request now: ready, their oldest request arrived. The others
    // keep their start times while this channel decides (only a served bank's changes), so the
    // earliest of them and of the served banks' next starts is the channel's next decision.
    Queued* const pool = c.pool.data();
    Bank* const banks = c.banks.data();
    uint64_t* const ready = c.ready.data();
    const size_t words = c.ready.size();
    uint64_t later = kNever;
    uint32_t ready_banks = 0;
    size_t last_ready = 0;  // with one ready bank, that bank
    for (size_t w = 0; w < words; ++w) {
      uint64_t bits = 0;
      for (uint64_t left = c.queued[w]; left; left &= left - 1) {
        const int bit = std::countr_zero(left);
        const size_t k = w * 64 + static_cast<size_t>(bit);
        const uint64_t at = banks[k].start_ps;
        const bool can_start = at <= now_ps;
        bits |= uint64_t{can_start} << bit;
        last_ready = can_start ? k : last_ready;
        ready_banks += can_start;
        later = std::min(later, can_start ? kNever : at);
      }
      ready[w] = bits;
    }
    while (ready_banks) {
      // FR-FCFS over the requests that can start now: row hits first, then age. Equal arrival
      // times go by address, so the order in which initiators happened to enqueue them (an
      // artefact of the simulation, not of the hardware) does not matter. A ready bank's best
      // row hit is its first request for the open row, if it has arrived; its oldest is its
      // queue's head.
      size_t k = last_ready;
      uint32_t best;
      if (ready_banks == 1) {
        best = banks[k].hit_arrival_ps <= now_ps ? banks[k].hit : banks[k].head;
      } else {
        uint32_t hit = kNil, oldest = kNil;
        size_t hit_bank = 0, oldest_bank = 0;
        for (size_t w = 0; w < words; ++w) {
          for (uint64_t left = ready[w]; left; left &= left - 1) {
            const size_t j = w * 64 + static_cast<size_t>(std::countr_zero(left));
            const Bank& b = banks[j];
            if (b.hit_arrival_ps <= now_ps && (hit == kNil || older(pool[b.hit], pool[hit]))) {
              hit = b.hit;
              hit_bank = j;
            }
            if (oldest == kNil || older(pool[b.head], pool[oldest])) {
              oldest = b.head;
              oldest_bank = j;
            }
          }
        }
        best = hit != kNil ? hit : oldest;
        k = hit != kNil ? hit_bank : oldest_bank;
      }
      Bank& b = banks[k];
      Queued& q = pool[best];
      const uint32_t next = q.next;
      (q.prev == kNil ? b.head : pool[q.prev].next) = next;
      (next == kNil ? b.tail : pool[next].prev) = q.prev;
      q.next = c.free;
      c.free = best;

      const uint64_t done = serve(c, b, q.row, q.req);
      out.push_back({q.req.id, done});
      // The bank's first request for its (new) open row comes after q: those before it were
      // for other rows (q was the first for the old open row, or the head).
      uint32_t h = next;
      while (h != kNil && pool[h].row != q.row) h = pool[h].next;
      b.hit = h;
      b.hit_arrival_ps = h == kNil ? kNever : pool[h].req.arrival_ps;
      if (b.head == kNil) {
        c.queued[k / 64] &= ~(uint64_t{1} << (k % 64));
        b.start_ps = kNever;
      } else {
        b.start_ps = start_at(pool[b.head].req, b);
      }
      if (b.start_ps > now_ps) {
        later = std::min(later, b.start_ps);
        if (--ready_banks == 0) break;
        ready[k / 64] &= ~(uint64_t{1} << (k % 64));
        if (ready_banks == 1) {  // the one left
          size_t w = 0;
          while (!ready[w]) ++w;
          last_ready = w * 64 + static_cast<size_t>(std::countr_zero(ready[w]));
        }
      }
    }
    next_decision = std::min(next_decision, later);
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
