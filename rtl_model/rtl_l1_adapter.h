// The RTL node L1 as a drop-in for L1Cache (l1.model = rtl): the Verilated l1_cache.sv driven
// through its valid/ready ports on a clock of the unit's period, behind the same TLM-2.0 AT
// sockets and counters (mem/node_l1.h).
//
// Protocol and timing (P = clock period; port semantics: rtl_model/README.md):
//  - A BEGIN_REQ from the unit at t = sc_time_stamp() + delay (rounded up to an edge) is
//    accepted at once (END_REQ) and queued; it is offered on i_req_* in the cycle [t, t+P) or,
//    when the port is busy, later, one request per cycle in arrival order, until o_req_ready.
//  - Each edge E samples the cycle it ends: an accepted request leaves the bus; o_resp_* is
//    answered upstream with BEGIN_RESP at E; o_mem_req_* goes to DRAM as a line READ at E.
//  - DRAM's BEGIN_RESP at F drives i_mem_resp_* in the cycle that ends at the first edge >= F
//    (one fill per cycle; the next waits a cycle). The RTL installs at that edge and answers
//    the waiting requests from the next cycle on.
//  So a hit is answered 2 cycles after t (as L1Cache with hit_cycles = 2) and a primary miss
//  2 cycles after L1Cache would answer it (the fill edge and the drain cycle); the line request
//  reaches DRAM at t + 2P in both.
//
// Clock and decoupling: the clock is a signal this module's thread drives (rising at edges,
// falling mid-cycle) only while the RTL has work: a request to offer, a fill to drive, a
// response or memory request on its outputs, or an MSHR draining. When only fills are awaited,
// the RTL's state cannot change until the fill: the clock stops and the thread sleeps until the
// next queued request or fill (a stopped clock is equivalent to idle edges). The module is a
// memory horizon for the unit: while clocking, the next edge (where a response may appear);
// idle, the edge after the next queued work, or never.
//
// Counters: hits, primary and merged misses from o_resp_hit/o_resp_merged; mshr_stall_cycles:
// cycles a request is offered and refused while all MSHRs are busy (the RTL's ports do not say
// why it refuses; other reasons, a fill cycle or a full response queue, are not counted);
// mean_miss_latency_cycles: primary misses, request time t to the response edge.
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

#include "mem/l1_cache.h"
#include "mem/mem_protocol.h"
#include "mem/node_l1.h"
#include "rtl_l1_sc.h"

namespace rtusim {

class RtlL1Adapter : public sc_core::sc_module, public NodeL1, public MemoryHorizon {
 public:
  tlm_utils::simple_target_socket<RtlL1Adapter> target_socket;        // from the unit
  tlm_utils::simple_initiator_socket<RtlL1Adapter> initiator_socket;  // to DRAM

  // `p`: geometry of a built combination (rtl/rtl_l1_registry.h, else InputError), mshrs 8,
  // hit_cycles 2 (CycleParams::finish checks). `vcd_path` non-empty: a VCD of clk and every
  // port signal (SystemC's tracer) written there.
  // `idle_while_awaiting_fills` false: the clock also runs while only fills are awaited (it
  // stops only when no request is outstanding); for the test that stopping it changes nothing.
  RtlL1Adapter(const sc_core::sc_module_name& name, const L1Params& p,
               const std::string& vcd_path = "", bool idle_while_awaiting_fills = true);
  ~RtlL1Adapter() override;

  SC_HAS_PROCESS(RtlL1Adapter);

  tlm::tlm_target_socket<>& upstream() override { return target_socket; }
  tlm::tlm_initiator_socket<>& downstream() override { return initiator_socket; }
  uint64_t hits() const override { return hits_; }
  uint64_t primary_misses() const override { return primary_; }
  uint64_t merged_misses() const override { return merged_; }
  uint64_t mshr_stall_cycles() const override { return stall_cycles_; }
  double mean_miss_latency_cycles() const override {
    return primary_ ? double(miss_latency_cycles_) / double(primary_) : 0.0;
  }
  uint64_t bytes_from_dram() const override { return primary_ * p_.cache.line_bytes; }
  const MemoryHorizon* horizon() const override { return this; }
  uint64_t horizon_ps() const override;

  uint64_t clocked_cycles() const { return clocked_cycles_; }  // edges actually simulated

 private:
  struct Request {
    uint64_t t_ps;
    uint32_t id;
  };
  struct Fill {
    uint64_t drive_ps;  // start of the cycle it is driven in
    uint64_t addr;
  };

  tlm::tlm_sync_enum nb_transport_fw(tlm::tlm_generic_payload& trans, tlm::tlm_phase& phase,
                                     sc_core::sc_time& delay);
  tlm::tlm_sync_enum nb_transport_bw(tlm::tlm_generic_payload& trans, tlm::tlm_phase& phase,
                                     sc_core::sc_time& delay);
  void run();
  void reset();
  void drive_cycle(uint64_t start_ps);
  void offer(const Request& r);
  void drive_fill(const Fill& f);
  void sample(uint64_t edge_ps);
  bool quiescent() const;
  uint64_t next_work_ps() const;  // earliest queued request or fill (unaligned), or kNever
  uint64_t align_up(uint64_t t) const { return (t + period_ - 1) / period_ * period_; }

  L1Params p_;
  uint64_t period_;
  bool idle_while_awaiting_fills_;
  uint32_t outstanding_ = 0;  // requests accepted from the unit and not yet answered
  sc_core::sc_signal<bool> clk_{"clk"};
  RtlL1Signals sig_;
  std::unique_ptr<sc_core::sc_module> rtl_;
  sc_core::sc_trace_file* vcd_ = nullptr;

  std::vector<tlm::tlm_generic_payload*> by_id_;  // upstream request per RTL id
  std::vector<uint64_t> t_by_id_;                 // its request time
  std::vector<uint32_t> free_ids_;
  std::deque<Request> queue_;     // waiting to be offered, by time
  bool offering_ = false;         // i_req_valid is high with `offered_`
  Request offered_{};
  bool filling_ = false;          // i_mem_resp_valid is high this cycle
  std::deque<Fill> fills_;        // by drive time
  uint32_t awaiting_fill_ = 0;    // line requests sent to DRAM and not yet driven back
  std::deque<tlm::tlm_generic_payload> mem_payloads_;  // each owns its FetchTag
  std::vector<tlm::tlm_generic_payload*> free_mem_payloads_;

  bool running_ = false;      // the clock is running
  bool cycle_open_ = false;   // inputs of the current cycle are driven (a request may join)
  uint64_t next_edge_ps_ = 0;  // while running
  sc_core::sc_event work_;

  uint64_t hits_ = 0, primary_ = 0, merged_ = 0, stall_cycles_ = 0, miss_latency_cycles_ = 0;
  uint64_t clocked_cycles_ = 0;
};

// The maker registered with the node L1 seam (mem/node_l1.h) when this library is linked.
std::unique_ptr<NodeL1> make_rtl_adapter(const char* name, const L1Params& p,
                                         const std::string& vcd_path);

}  // namespace rtusim
