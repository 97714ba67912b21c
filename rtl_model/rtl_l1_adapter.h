// The RTL node L1 as a drop-in for L1Cache (l1.model = rtl): the Verilated l1_cache.sv driven
// through its ports on a clock of the unit's period, behind the same TLM-2.0 AT sockets and
// counters (mem/node_l1.h). Both implement the node L1 timing spec v2 (the header of
// mem/l1_cache.h; ports and timing of the RTL: rtl_model/README.md).
//
// Mapping (P = clock period, cycle c = [cP, (c+1)P); a request's time t = its payload time
// rounded up to an edge, in cycles; H = 2):
//  - Requests: a FIFO in arrival order. The head is offered (i_req_*) in cycle
//    max(t, previous lookup + 1) and every following cycle until o_req_ready: the lookup cycle
//    c. At the edge (c+1)P the adapter reads o_req_hit / o_req_merged / o_req_mshr and counts
//    the outcome; a miss joins the waiter list of o_req_mshr (the RTL keeps none).
//  - Hits: o_resp_valid / o_resp_id in cycle c+1, answered upstream at the edge (c+2)P.
//  - Line reads: o_mem_req_valid in cycle c+1 (i_mem_req_ready is always high, so the RTL
//    hands the read over at the edge (c+2)P). The READ's time at DRAM is that edge; the adapter
//    sends it as soon as the output shows it, at the start of cycle c+1, annotated with (c+2)P,
//    so DRAM holds it before it decides anything at (c+2)P (as it holds L1Cache's read, sent
//    when its lookup is decided).
//  - Fills: DRAM's BEGIN_RESP tells the completion F (at its decision time, long before F). The
//    fill cycle T is the first cycle >= ceil(F/P) no other fill holds, taken in the order the
//    answers arrive; i_mem_resp_* is driven in cycle T-1 and at the edge TP every waiter of
//    o_fill_mshr is answered (after the acceptance of that edge, so a merge in cycle T-1 is
//    answered too). Cycle T-1 may be driven until its edge (the RTL samples inputs only
//    there): told F while the clock stands still in cycle T-1, the clock starts mid-cycle.
//    Learning F after cycle T-1 was driven is a logic_error.
//  - Order of the answers at one edge: the fill's waiters in lookup order (the primary first),
//    then the hit.
//
// Counters (spec item 5): hits, primary and merged misses at acceptance; mshr_stall_cycles:
// cycles the head is offered and refused (the adapter is always ready for responses, so a
// refusal means every MSHR is busy); mean_miss_latency_cycles: fill cycle T - t over primary
// misses.
//
// Clock and decoupling: the clock is a signal this module's thread drives (rising at edges)
// only while the RTL has work: a request to offer, a fill to drive, a hit or line read on its
// outputs. Otherwise its state cannot change before the next queued request or fill, so the
// clock stops until then (a stopped clock is equivalent to idle edges); that includes a head
// refused for want of an MSHR, which waits, offered, for the next fill. The module is a memory
// horizon for the unit, the earliest time it may answer something the unit does not know yet:
// while clocking, the next edge if an answer leaves there (a hit on o_resp_valid, a fill),
// else the edge after; idle, the first known fill's edge or two cycles after the head's lookup
// cycle, or never.
#pragma once
#include <array>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
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
#include "util/output_files.h"

namespace rtusim {

class RtlL1Adapter : public sc_core::sc_module, public NodeL1, public MemoryHorizon {
 public:
  tlm_utils::simple_target_socket<RtlL1Adapter> target_socket;        // from the unit
  tlm_utils::simple_initiator_socket<RtlL1Adapter> initiator_socket;  // to DRAM

  // `p`: geometry of a built combination (rtl/rtl_l1_registry.h, else InputError), mshrs 8,
  // hit_cycles 2 (CycleParams::finish checks). `vcd_path` non-empty: a VCD of clk and every
  // port signal (SystemC's tracer), written under a temporary name and renamed to `vcd_path`
  // by finish() (called when the run succeeded; otherwise the destructor removes it).
  // `idle_while_awaiting_fills` false: the clock also runs while only fills are awaited (it
  // stops only when no request is outstanding); for the test that stopping it changes nothing.
  RtlL1Adapter(const sc_core::sc_module_name& name, const L1Params& p,
               const std::string& vcd_path = "", bool idle_while_awaiting_fills = true);
  ~RtlL1Adapter() override;  // drops the VCD unless finish() committed it
  void finish() override;    // closes the VCD and moves it into place

  SC_HAS_PROCESS(RtlL1Adapter);

  tlm::tlm_target_socket<>& upstream() override { return target_socket; }
  tlm::tlm_initiator_socket<>& downstream() override { return initiator_socket; }
  uint64_t hits() const override { return hits_; }
  uint64_t primary_misses() const override { return primary_; }
  uint64_t merged_misses() const override { return merged_; }
  uint64_t mshr_stall_cycles() const override { return stall_cycles_; }
  double mean_miss_latency_cycles() const override {
    return fills_done_ ? double(miss_latency_cycles_) / double(fills_done_) : 0.0;
  }
  uint64_t bytes_from_dram() const override { return primary_ * p_.cache.line_bytes; }
  const MemoryHorizon* horizon() const override { return this; }
  uint64_t horizon_ps() const override;

  uint64_t clocked_cycles() const { return clocked_cycles_; }  // edges actually simulated

 private:
  static constexpr uint64_t kNone = ~uint64_t{0};
  struct Request {
    tlm::tlm_generic_payload* trans = nullptr;
    uint64_t t = 0;  // request time (cycle)
  };

  tlm::tlm_sync_enum nb_transport_fw(tlm::tlm_generic_payload& trans, tlm::tlm_phase& phase,
                                     sc_core::sc_time& delay);
  tlm::tlm_sync_enum nb_transport_bw(tlm::tlm_generic_payload& trans, tlm::tlm_phase& phase,
                                     sc_core::sc_time& delay);
  void run();
  void reset();
  // Drives the inputs of cycle `c` (its edge is at (c+1)P).
  void drive_cycle(uint64_t c);
  void offer(uint32_t id, uint64_t c);
  void drive_fill(uint64_t addr);
  // Reads the outputs of the cycle that the edge at `edge_ps` ends and acts on them.
  void sample(uint64_t edge_ps);
  void answer(uint32_t id, uint64_t edge_ps);
  void send_line_read(uint64_t addr, sc_core::sc_time delay);  // a READ of the line at now + delay
  bool quiescent() const;
  uint64_t first_drivable_cycle() const;  // the earliest cycle whose inputs are not fixed yet
  uint64_t head_lookup_cycle() const;     // the queue head's lookup cycle if offered next
  uint64_t next_work_cycle() const;       // idle: the first cycle to clock again, or kNone
  uint64_t cycle_at_or_after(uint64_t t_ps) const { return (t_ps + period_ - 1) / period_; }
  void open_vcd(const std::string& path);

  L1Params p_;
  uint64_t period_;
  bool idle_while_awaiting_fills_;
  sc_core::sc_signal<bool> clk_{"clk"};
  RtlL1Signals sig_;
  std::unique_ptr<sc_core::sc_module> rtl_;

  // Requests: the id the RTL carries indexes `requests_`.
  std::vector<Request> requests_;
  std::vector<uint32_t> free_ids_;
  uint32_t outstanding_ = 0;  // accepted from the unit, not answered yet
  std::deque<uint32_t> queue_;  // not offered yet, arrival order
  bool offering_ = false;       // i_req_valid is high with `offered_`
  uint32_t offered_ = 0;
  uint64_t offered_since_ = 0;  // the cycle it was first offered
  uint64_t last_lookup_ = kNone;  // the latest lookup cycle

  // MSHRs as the adapter sees them: waiters (lookup order) and the primary's request time.
  std::array<std::vector<uint32_t>, RtlL1Fixed::kMshrs> waiters_;
  std::array<uint64_t, RtlL1Fixed::kMshrs> primary_t_{};

  // Fills by fill cycle T (one per cycle), from DRAM's answer until the edge TP.
  std::map<uint64_t, uint64_t> fills_;  // T -> line address
  bool filling_ = false;                // i_mem_resp_valid is high this cycle
  std::deque<tlm::tlm_generic_payload> mem_payloads_;  // each owns its FetchTag
  std::vector<tlm::tlm_generic_payload*> free_mem_payloads_;

  bool running_ = false;     // the clock is running
  bool cycle_open_ = false;  // the inputs of cycle `cycle_` are driven (before its edge)
  uint64_t cycle_ = 0;
  bool answer_at_edge_ = false;  // an answer leaves at the edge ending `cycle_`
  sc_core::sc_event work_;

  sc_core::sc_trace_file* vcd_ = nullptr;
  std::optional<OutputFile> vcd_file_;  // where the VCD goes; SystemC adds ".vcd" to its name

  uint64_t hits_ = 0, primary_ = 0, merged_ = 0, stall_cycles_ = 0;
  uint64_t fills_done_ = 0, miss_latency_cycles_ = 0;
  uint64_t clocked_cycles_ = 0;
};

// The maker registered with the node L1 seam (mem/node_l1.h) when this library is linked.
std::unique_ptr<NodeL1> make_rtl_adapter(const char* name, const L1Params& p,
                                         const std::string& vcd_path);

}  // namespace rtusim
