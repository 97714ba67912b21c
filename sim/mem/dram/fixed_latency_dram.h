// The cheapest DRAM timing model (dram.backend = "fixed"): every read takes a fixed latency
// (dram.latency_ns) and then its bursts on its channel's data bus (the bandwidth of
// dram.data_rate_mts x dram.bus_bytes). No banks, no rows: requests are served in arrival order
// (equal arrivals by address) per channel, channel = (addr / row_bytes) mod channels.
//   done = max(arrival + latency, bus free) + bursts x tBurst;  bus free = done.
// A rung below FR-FCFS on the accuracy ladder: the same bytes, a simpler time.
#pragma once
#include <vector>

#include "mem/dram/dram_backend.h"
#include "mem/dram/dram_params.h"
#include "mem/fast_divider.h"

namespace rtusim {

class FixedLatencyDram final : public DramBackend {
 public:
  static constexpr const char* kName = "fixed";
  static constexpr const char* kSummary = "a fixed latency, then the bus";

  // Validates `p` (keys named "dram.*").
  explicit FixedLatencyDram(const DramParams& p);

  void enqueue(const DramRequest& r) override;
  uint64_t next_decision_ps() const override { return next_decision_ps_; }
  void advance(uint64_t now_ps, std::vector<DramCompletion>& out) override;
  // `prefix`.requests and .bytes.{nodes,lists,triangles,total}.
  void write_stats(Stats& stats, const std::string& prefix) const override;

 private:
  struct Queued {
    DramRequest req;
    uint64_t seq;  // enqueue order: the last tie-break
  };
  struct Channel {
    std::vector<Queued> queue;  // unordered; served by (arrival, address, seq)
    uint64_t bus_free_ps = 0;
  };

  Channel& channel_of(uint64_t addr) { return channels_[channel_.mod(row_.div(addr))]; }
  // Serves `r` on `c` (arrived, first in line): counts it, books the bus; returns its done_ps.
  uint64_t serve(Channel& c, const DramRequest& r);

  DramParams p_;
  uint64_t latency_ps_, tBurst_ps_;
  FastDivider row_, channel_, burst_;  // address to row chunk, chunk to channel; bytes to bursts
  std::vector<Channel> channels_;
  uint64_t next_decision_ps_ = kNever;
  uint64_t seq_ = 0;
};

}  // namespace rtusim
