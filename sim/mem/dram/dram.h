// The DRAM as a SystemC module: a TLM-2.0 AT target (any number of initiators bind to
// `target_socket`) around a DramBackend timing model.
//
// BEGIN_REQ is accepted at once (TLM_UPDATED, END_REQ) and queued with arrival time
// sc_time_stamp() + delay. A method wakes at each time a scheduling decision is due, lets the
// backend decide, and sends BEGIN_RESP for every scheduled request with the delay to its
// completion. The module is its own memory horizon: nothing happens here before the next
// decision time. Driven by call (CallDriven, mem_protocol.h), the method is not woken: the
// initiator makes the decisions at the horizon itself, ahead of the kernel.
// The horizon promises that every completion an initiator does not know yet comes after it. The
// decisions of one time are answered one by one, and an initiator may act in the callback of
// one answer (an L1 decides the lookups its fill unblocks): while a batch is answered, the
// earliest completion of the batch not answered yet bounds the horizon too.
#pragma once
#include <algorithm>
#include <memory>
#include <vector>

#include <systemc>
#include <tlm>
#include <tlm_utils/multi_passthrough_target_socket.h>

#include "mem/dram/dram_backend.h"
#include "mem/dram/dram_params.h"
#include "mem/mem_protocol.h"

namespace rtusim {

class Dram final : public sc_core::sc_module, public MemoryHorizon, public CallDriven,
                   public DirectTarget {
 public:
  tlm_utils::multi_passthrough_target_socket<Dram> target_socket;

  // The timing model named by p.backend (dram_backends.h), validated; errors name "dram.*".
  Dram(const sc_core::sc_module_name& name, const DramParams& p);
  // Another timing model behind the same socket.
  Dram(const sc_core::sc_module_name& name, std::unique_ptr<DramBackend> backend);

  SC_HAS_PROCESS(Dram);

  uint64_t horizon_ps() const override { return horizon_ps_; }
  const uint64_t* horizon_word() const override { return &horizon_ps_; }
  bool reports_changes() const override { return true; }
  // A module is never a const object: the horizon view hands out the module to drive.
  CallDriven* call_driven() const override { return const_cast<Dram*>(this); }
  void set_driven_by_call(bool on) override {
    driven_by_call_ = on;
    if (!on) schedule_wakeup();  // its process takes over from here
  }
  void act_at_horizon(uint64_t at_ps) override { decide_at(at_ps); }
  // A read by direct call (what nb_transport_fw does, in picoseconds): always answered later,
  // by direct call to the payload's FetchTag::reply_to, which it must name.
  bool read_at(tlm::tlm_generic_payload& trans, uint64_t at_ps, uint64_t* done_ps) override {
    return read_tagged_at(trans, trans.get_extension<FetchTag>(), at_ps, done_ps);
  }
  bool read_tagged_at(tlm::tlm_generic_payload& trans, const FetchTag* tag, uint64_t at_ps,
                      uint64_t* done_ps) override;
  const DramBackend& backend() const { return *backend_; }

 private:
  struct Pending {
    tlm::tlm_generic_payload* trans;
    int socket_id;
    DirectInitiator* reply_to;  // answered by direct call to it, if not nullptr
  };

  tlm::tlm_sync_enum nb_transport_fw(int id, tlm::tlm_generic_payload& trans,
                                     tlm::tlm_phase& phase, sc_core::sc_time& delay);
  // Queues a READ (`tag`: its FetchTag, or nullptr) that reaches the controller at
  // `arrival_ps`, answered through socket `socket_id` or, if not nullptr, by direct call to
  // `reply_to`.
  void accept(tlm::tlm_generic_payload& trans, const FetchTag* tag, int socket_id,
              DirectInitiator* reply_to, uint64_t arrival_ps);
  void decide();  // SC_METHOD: the decisions due at the kernel's time
  // Makes the decisions due at `at_ps` (>= the kernel's time) and answers them.
  void decide_at(uint64_t at_ps);
  void schedule_wakeup();

  std::unique_ptr<DramBackend> backend_;
  std::vector<Pending> pending_;     // by request id
  std::vector<uint64_t> free_ids_;
  std::vector<DramCompletion> done_;  // scratch
  std::vector<uint64_t> later_done_ps_;  // scratch: per answer, the earliest completion after it
  uint64_t unanswered_ps_ = kNever;  // just before the earliest decided completion not answered
  // The backend's next decision or unanswered_ps_, whichever is first: kept up to date at each
  // change of either (the initiators ask for it several times per fetch).
  uint64_t horizon_ps_ = kNever;
  void update_horizon() {
    const uint64_t h = std::min(backend_->next_decision_ps(), unanswered_ps_);
    if (h == horizon_ps_) return;
    horizon_ps_ = h;
    horizon_changed();
  }
  sc_core::sc_event wake_;
  bool driven_by_call_ = false;  // the initiator calls act_at_horizon(): no wake-ups
  bool wake_pending_ = false;  // wake_ is notified for wake_ps_
  uint64_t wake_ps_ = 0;
};

}  // namespace rtusim
