// The seam between the DRAM SystemC module and a DRAM timing model, so another DRAM simulator
// (Ramulator, DRAMSys' controller, ...) can be plugged in behind the same TLM target.
//
// Protocol: the module enqueues requests as they arrive (in non-decreasing arrival time from any
// one initiator), asks for the next time a scheduling decision is due, and at that simulated
// time calls advance(), which makes every decision due by then and reports each scheduled
// request with the time its data transfer completes (a time in the future of `now_ps`).
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "layout/memory_image.h"

namespace rtusim {

class Stats;

struct DramRequest {
  uint64_t id = 0;          // chosen by the caller, returned in the completion
  uint64_t addr = 0;
  uint32_t bytes = 0;       // counted as asked; takes whole bursts of bus time (a shorter
                            // one is a burst chop)
  uint64_t arrival_ps = 0;  // when the request reaches the controller's queue
  Stream stream = Stream::kNode;
};

struct DramCompletion {
  uint64_t id = 0;
  uint64_t done_ps = 0;  // last data beat on the bus
};

class DramBackend {
 public:
  static constexpr uint64_t kNever = std::numeric_limits<uint64_t>::max();

  virtual ~DramBackend() = default;
  virtual void enqueue(const DramRequest& r) = 0;
  // Earliest time a queued request can be scheduled; kNever when the queue is empty.
  virtual uint64_t next_decision_ps() const = 0;
  // Makes every decision due at or before `now_ps`; appends one completion per scheduled request.
  virtual void advance(uint64_t now_ps, std::vector<DramCompletion>& out) = 0;
  // Writes `prefix`.requests, .bytes.{nodes,lists,triangles,total} and the model's own keys
  // (FR-FCFS: .row_hits, .row_misses, .row_conflicts, .row_hit_rate).
  virtual void write_stats(Stats& stats, const std::string& prefix) const = 0;
  // Bytes transferred per stream.
  uint64_t bytes(Stream s) const { return bytes_[static_cast<int>(s)]; }

 protected:
  // Counts a scheduled request's bytes.
  void count(const DramRequest& r) {
    ++requests_;
    bytes_[static_cast<int>(r.stream)] += r.bytes;
  }
  // `prefix`.requests and .bytes.{nodes,lists,triangles,total}.
  void write_request_stats(Stats& stats, const std::string& prefix) const;

 private:
  uint64_t requests_ = 0;
  std::array<uint64_t, 3> bytes_{};
};

}  // namespace rtusim
