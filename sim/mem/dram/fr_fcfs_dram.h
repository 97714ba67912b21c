// A DRAM timing model: open-row policy, per-bank row state, one data bus per channel, and a
// request queue per channel scheduled first-ready, first-come-first-served (FR-FCFS: among the
// requests whose bank is ready, the oldest row hit goes first, else the oldest request).
//
// Timing of a request scheduled at time T on bank b (T = max(arrival, b.ready)):
//   row hit      (b's open row is the request's): column command at T
//   row miss     (b has no open row):             column command at T + tRCD
//   row conflict (b has another row open):        column command at T + tRP + tRCD
//   data on the bus from max(column + tCL, bus free) for bursts x tBurst; done at its end;
//   b.ready = column + bursts x tBurst (the next column command to the bank).
// An isolated request therefore takes tCL + tBurst (hit), tRCD + tCL + tBurst (miss) or
// tRP + tRCD + tCL + tBurst (conflict). Not modelled: refresh, tRAS/tRC/tFAW/tRRD, bank groups,
// the command bus, writes (the unit only reads).
#pragma once
#include <algorithm>
#include <vector>

#include "mem/dram/dram_backend.h"
#include "mem/dram/dram_params.h"
#include "mem/fast_divider.h"

namespace rtusim {

class FrFcfsDram final : public DramBackend {
 public:
  static constexpr const char* kName = "fr-fcfs";
  static constexpr const char* kSummary = "banks, open rows, FR-FCFS per channel";

  // Validates `p` (keys named "dram.*").
  explicit FrFcfsDram(const DramParams& p);

  void enqueue(const DramRequest& r) override;
  uint64_t next_decision_ps() const override { return next_decision_ps_; }
  void advance(uint64_t now_ps, std::vector<DramCompletion>& out) override;
  void write_stats(Stats& stats, const std::string& prefix) const override;

  struct Location {
    uint32_t channel, bank;
    uint64_t row;
  };
  Location locate(uint64_t addr) const;

  uint64_t row_hits() const { return row_hits_; }
  uint64_t row_misses() const { return row_misses_; }
  uint64_t row_conflicts() const { return row_conflicts_; }

 private:
  static constexpr uint64_t kNoRow = ~uint64_t{0};
  static constexpr uint32_t kNil = ~uint32_t{0};
  struct Queued {
    DramRequest req;
    uint64_t row;
    uint64_t seq;  // enqueue order: the last tie-break (after arrival time, then address)
    uint32_t prev = kNil, next = kNil;  // the neighbours in its bank's queue (Bank::head)
  };
  struct Bank {
    uint64_t open_row = kNoRow;
    uint64_t ready_ps = 0;
    // Its queue, oldest first (older()), a list threaded through Channel::pool from head to
    // tail; `hit` is its first request for the open row (kNil: none).
    uint32_t head = kNil, tail = kNil, hit = kNil;
    uint64_t start_ps = kNever;        // when its oldest request can start (kNever: queue empty)
    uint64_t hit_arrival_ps = kNever;  // `hit`'s arrival (kNever: none)
  };
  // A request's age: (arrival, address, seq), a total order (seq is unique). Compared without
  // branches, (arrival, address) as one 128-bit number: the outcome is not predictable.
  static bool older(const Queued& a, const Queued& b) {
    __extension__ typedef unsigned __int128 Key;
    const Key ka = Key{a.req.arrival_ps} << 64 | a.req.addr;
    const Key kb = Key{b.req.arrival_ps} << 64 | b.req.addr;
    return (ka < kb) | ((ka == kb) & (a.seq < b.seq));
  }
  struct Channel {
    std::vector<Queued> pool;
    uint32_t free = kNil;  // the pool entries in no bank's queue, a list through Queued::next
    std::vector<Bank> banks;
    // Bit k % 64 of word k / 64: bank k's queue is not empty; bank k can start a request now
    // (advance()'s scratch).
    std::vector<uint64_t> queued, ready;
    uint64_t bus_free_ps = 0;
  };

  // When `r` can start on bank `b`: the later of its arrival and the bank's ready time.
  static uint64_t start_at(const DramRequest& r, const Bank& b) {
    return std::max(r.arrival_ps, b.ready_ps);
  }
  // Schedules `r` (row `row`) on bank `b` of `c` at its start_at(): counts it, books the bank
  // and the bus; returns its done_ps.
  uint64_t serve(Channel& c, Bank& b, uint64_t row, const DramRequest& r);

  DramParams p_;
  uint64_t tRCD_ps_, tRP_ps_, tCL_ps_, tBurst_ps_;
  FastDivider row_, channel_, bank_, burst_;  // address to row, channel, bank; bytes to bursts
  std::vector<Channel> channels_;
  uint64_t next_decision_ps_ = kNever;
  uint64_t seq_ = 0;
  uint64_t row_hits_ = 0, row_misses_ = 0, row_conflicts_ = 0;
  uint64_t busy_until_ps_ = 0;
};

// Inline: called once per DRAM request (enqueue, and the timed engine through the queue).
inline FrFcfsDram::Location FrFcfsDram::locate(uint64_t addr) const {
  const uint64_t chunk = row_.div(addr);
  const uint64_t per_channel = channel_.div(chunk);
  Location l;
  l.channel = static_cast<uint32_t>(chunk - per_channel * p_.channels);
  l.bank = static_cast<uint32_t>(bank_.mod(per_channel));
  l.row = bank_.div(per_channel);
  return l;
}

inline uint64_t FrFcfsDram::serve(Channel& c, Bank& b, uint64_t row, const DramRequest& r) {
  uint64_t column = start_at(r, b);
  if (b.open_row == row) {
    ++row_hits_;
  } else if (b.open_row == kNoRow) {
    ++row_misses_;
    column += tRCD_ps_;
  } else {
    ++row_conflicts_;
    column += tRP_ps_ + tRCD_ps_;
  }
  const uint32_t bursts = std::max<uint32_t>(1, burst_.div_up(r.bytes));
  const uint64_t data_start = std::max(column + tCL_ps_, c.bus_free_ps);
  const uint64_t done = data_start + bursts * tBurst_ps_;
  c.bus_free_ps = done;
  b.open_row = row;
  b.ready_ps = column + bursts * tBurst_ps_;
  count(r);
  busy_until_ps_ = std::max(busy_until_ps_, done);
  return done;
}

}  // namespace rtusim
