// A non-blocking read cache as a SystemC module: the tag store and replacement of the
// behavioural SetAssocCache (so its hit/miss decisions are the functional tier's, given the same
// access order), plus hit latency, MSHRs and TLM-2.0 AT sockets (see mem_protocol.h).
//
// Each upstream request reads bytes within one line, at time t = sc_time_stamp() + delay (on a
// clock edge). Per request, in arrival order:
//  - an MSHR is outstanding for its line at t: a merged (secondary) miss; the tag store's
//    replacement state is updated (access()); the data comes with that MSHR's fill;
//  - the line is in the tag store: a hit, TLM_COMPLETED with the data at t + hit_cycles;
//  - else a primary miss, which needs an MSHR. An MSHR is busy from its allocation to its fill
//    (the downstream completion, rounded up to a clock edge). If all are busy at t, the request
//    stalls (so does every later miss while one is stalled; hits go on) until the first time T
//    an MSHR is free, known as soon as that fill time is known, and then goes on as a miss at T.
//    The tag store fills the line at once (allocate on miss, as the behavioural cache does) and a
//    line read goes downstream at T + hit_cycles; at the fill every request on the MSHR gets
//    BEGIN_RESP.
// Counters: hits, primary and merged misses, mshr_stall_cycles (summed over stalled requests:
// the cycles each waited for an MSHR) and the mean primary miss latency (request to fill,
// stall included).
// Tag-store updates happen in the order requests are presented, which is time order except
// that a stalled request updates it when its MSHR time T becomes known.
#pragma once
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include <systemc>
#include <tlm>
#include <tlm_utils/simple_initiator_socket.h>
#include <tlm_utils/simple_target_socket.h>

#include "cache/cache_params.h"
#include "cache/set_assoc_cache.h"
#include "mem/mem_protocol.h"
#include "mem/node_l1.h"

namespace rtusim {

class Stats;

struct L1Params {
  CacheParams cache;              // geometry and replacement (l1.size/assoc/line/policy)
  uint32_t hit_cycles = 2;        // tag + data access
  uint32_t mshrs = 8;             // outstanding line misses
  uint64_t clock_period_ps = 1000;
};

// Throws InputError naming `prefix`.hit_cycles / .mshrs / the cache keys.
void validate(const L1Params& p, const std::string& prefix);

class L1Cache : public sc_core::sc_module, public NodeL1 {
 public:
  tlm_utils::simple_target_socket<L1Cache> target_socket;        // from the unit
  tlm_utils::simple_initiator_socket<L1Cache> initiator_socket;  // to DRAM

  L1Cache(const sc_core::sc_module_name& name, const L1Params& p);

  tlm::tlm_target_socket<>& upstream() override { return target_socket; }
  tlm::tlm_initiator_socket<>& downstream() override { return initiator_socket; }

  uint64_t hits() const override { return hits_; }
  uint64_t primary_misses() const override { return primary_; }
  uint64_t merged_misses() const override { return merged_; }
  uint64_t mshr_stall_cycles() const override { return stall_cycles_; }
  double mean_miss_latency_cycles() const override {
    return fills_ ? double(miss_latency_cycles_) / double(fills_) : 0.0;
  }
  uint64_t bytes_from_dram() const override { return primary_ * line_bytes_; }
  const SetAssocCache& tags() const { return tags_; }
  const L1Params& params() const { return p_; }

  // Writes `prefix`.{accesses,hits,misses,primary_misses,merged_misses,mshr_stall_cycles,
  // mean_miss_latency_cycles}.

 private:
  static constexpr uint64_t kUnknown = ~uint64_t{0};
  struct Waiter {
    tlm::tlm_generic_payload* trans;
    uint64_t t_ps;
  };
  struct MshrPort {  // what a miss needs besides its times: kept off the scanned array
    std::vector<tlm::tlm_generic_payload*> waiters;
    tlm::tlm_generic_payload payload;
    FetchTag* tag = nullptr;  // owned by the payload (it deletes its extensions)
  };
  struct Mshr {
    bool in_use = false;
    uint64_t line = 0;
    uint64_t request_ps = 0;  // the primary request's arrival
    uint64_t alloc_ps = 0;    // busy from here ...
    uint64_t fill_ps = kUnknown;  // ... to here (unknown until the downstream answers)
    std::unique_ptr<MshrPort> port;
    bool busy_at(uint64_t t) const { return in_use & (alloc_ps <= t) & (t < fill_ps); }
  };
  struct Result {
    enum Kind { kDone, kPending, kStalled } kind;
    uint64_t at_ps;  // kDone: when the data is there
  };

  tlm::tlm_sync_enum nb_transport_fw(tlm::tlm_generic_payload& trans, tlm::tlm_phase& phase,
                                     sc_core::sc_time& delay);
  tlm::tlm_sync_enum nb_transport_bw(tlm::tlm_generic_payload& trans, tlm::tlm_phase& phase,
                                     sc_core::sc_time& delay);
  // One access at time t_ps (a clock edge) of a request that arrived at request_ps; `retry`:
  // a stalled request presented again (it does not queue behind the other stalled ones).
  Result access(tlm::tlm_generic_payload& trans, uint64_t t_ps, uint64_t request_ps,
                bool retry);
  // Earliest time >= t with a free MSHR given the fills known so far; kUnknown if none.
  uint64_t free_mshr_time(uint64_t t) const;
  void set_fill(Mshr& m, uint64_t done_ps);
  void retry_stalled();
  void respond(tlm::tlm_generic_payload& trans, uint64_t at_ps);
  uint64_t align_up(uint64_t t_ps) const {
    return (t_ps + p_.clock_period_ps - 1) / p_.clock_period_ps * p_.clock_period_ps;
  }

  L1Params p_;
  SetAssocCache tags_;
  uint32_t offset_bits_;
  uint64_t line_bytes_;
  uint64_t hit_ps_;
  sc_core::sc_time hit_time_;
  std::vector<Mshr> mshrs_;  // busy or recently filled (reused once the kernel passes the fill)
  std::deque<Waiter> stalled_;
  uint64_t hits_ = 0, primary_ = 0, merged_ = 0, stall_cycles_ = 0;
  uint64_t fills_ = 0, miss_latency_cycles_ = 0;
};

}  // namespace rtusim
