// What the cycle tier's TLM-2.0 modules share: the payload tag, the memory horizon, time helpers.
//
// Protocol: TLM-2.0 approximately-timed base protocol (nb_transport_fw/bw, generic payload,
// READ only). Chosen over loosely-timed because the DRAM schedules FR-FCFS: a request's
// completion time depends on requests that arrive after it (a later row hit overtakes an older
// row miss), so a target cannot answer in b_transport when the request arrives; with AT it
// accepts the request (END_REQ) and answers later with BEGIN_RESP. Every call carries an
// annotated delay (the payload's time is sc_time_stamp() + delay), so an initiator may run ahead
// of the kernel (temporal decoupling) and a target may answer with a completion time in the
// future; the receiver treats the annotation as the event time (its own event queue acts as the
// payload event queue). A target may also complete at once (TLM_COMPLETED, e.g. a cache hit).
//
// The memory horizon bounds the decoupling: the earliest time at which a memory component will
// act on its own (a DRAM scheduling decision). An initiator that runs ahead must not process an
// event at or after the horizon before the kernel has reached it; until then nothing it has not
// already been told about can happen, so it advances without context switches.
#pragma once
#include <cstdint>
#include <limits>
#include <vector>

#include <systemc>
#include <tlm>

#include "layout/memory_image.h"

namespace rtusim {

class DirectInitiator;

// Tags a payload with its fetch stream and its owner's index (a ray slot, an MSHR), and the
// initiator that takes its answer by direct call, if any.
struct FetchTag : tlm::tlm_extension<FetchTag> {
  Stream stream = Stream::kNode;
  uint32_t owner = 0;
  // nullptr: BEGIN_RESP through the socket. Copied with the tag: a module that copies tags onto
  // payloads it sends on must clear it, or the answer would bypass that module.
  DirectInitiator* reply_to = nullptr;
  tlm::tlm_extension_base* clone() const override { return new FetchTag(*this); }
  void copy_from(const tlm::tlm_extension_base& other) override {
    *this = static_cast<const FetchTag&>(other);
  }
};

// A memory component that can be driven by call: it acts only at its horizon, on what it was
// sent, so an initiator that bounds its run-ahead by every memory component's horizon can act
// for it there instead of letting the kernel get there (no context switch per decision: the
// memory side runs ahead of the kernel with the initiator).
class CallDriven {
 public:
  virtual ~CallDriven() = default;
  // From now on driven by call only (its own process is not woken) or by its process again.
  virtual void set_driven_by_call(bool on) = 0;
  // Does now what the component's process would do when the kernel reached `at_ps` (its
  // horizon, at or after the kernel's time); answers carry delays from the kernel's time.
  virtual void act_at_horizon(uint64_t at_ps) = 0;
};

// A target that also takes reads by direct call, in integer picoseconds: what nb_transport_fw
// does with BEGIN_REQ and an annotated delay, without sc_time arithmetic or the socket. Only
// for an initiator bound to this target's socket; later answers come by direct call when the
// payload's FetchTag names a reply_to (DirectInitiator), else as BEGIN_RESP on the socket.
class DirectTarget {
 public:
  virtual ~DirectTarget() = default;
  // A read at absolute time `at_ps` (at or after the kernel's time). True: completed at once
  // (the response status set; *done_ps its time); false: answered later (reply_to or BEGIN_RESP).
  virtual bool read_at(tlm::tlm_generic_payload& trans, uint64_t at_ps, uint64_t* done_ps) = 0;
  // read_at() of a payload whose FetchTag (nullptr: none) the caller hands in, so the target
  // need not look it up (get_extension() is a library call).
  virtual bool read_tagged_at(tlm::tlm_generic_payload& trans, const FetchTag* tag,
                              uint64_t at_ps, uint64_t* done_ps) {
    (void)tag;
    return read_at(trans, at_ps, done_ps);
  }
};

// An initiator that also takes answers by direct call: what its nb_transport_bw does with
// BEGIN_RESP (the response status set), at absolute time `at_ps`, without the socket or sc_time
// arithmetic. A target answers so every payload whose FetchTag names the initiator (reply_to).
// An initiator names itself only on the reads it sends by direct call (DirectTarget::read_at),
// never on those it sends through its socket: a module in between (a recorder, an adapter)
// sees every answer to what passed through it.
class DirectInitiator {
 public:
  virtual ~DirectInitiator() = default;
  virtual void answered(tlm::tlm_generic_payload& trans, uint64_t at_ps) = 0;
};

class MemoryHorizon {
 public:
  static constexpr uint64_t kNever = std::numeric_limits<uint64_t>::max();
  virtual ~MemoryHorizon() = default;
  // Earliest absolute time (ps) at which this component acts on its own; kNever if idle.
  virtual uint64_t horizon_ps() const = 0;
  // Where the component keeps its horizon, always equal to horizon_ps() (read without a call),
  // or nullptr if it computes it when asked.
  virtual const uint64_t* horizon_word() const { return nullptr; }
  // The component as CallDriven, or nullptr if only its own process may act (then an
  // initiator must let the kernel reach the horizon).
  virtual CallDriven* call_driven() const { return nullptr; }
  // Whether the component sets every watched flag (watch()) whenever its horizon changes, so an
  // initiator may keep the horizon it last asked for until then; false: ask every time.
  virtual bool reports_changes() const { return false; }
  // `flag` is set (never cleared) at each change of the horizon, if reports_changes(). The
  // component keeps the pointer: the flag must outlive it (or the component stop acting first).
  void watch(bool* flag) const { watchers_.push_back(flag); }

 protected:
  void horizon_changed() const {
    for (bool* f : watchers_) *f = true;
  }

 private:
  mutable std::vector<bool*> watchers_;  // watching does not change the component
};

// Both inline: sc_time_stamp() and sc_time::from_value() are calls into the SystemC library,
// made several times per simulated fetch.
inline uint64_t now_ps() {  // resolution is 1 ps
  return sc_core::sc_get_curr_simcontext()->time_stamp().value();
}
inline sc_core::sc_time ps(uint64_t v) {
  // 1 ps scaled by v: exact below 2^52 (sc_time adds 0.5 to the double product and truncates).
  static const sc_core::sc_time kOnePs = sc_core::sc_time::from_value(1);
  if (v >= (uint64_t{1} << 52)) [[unlikely]] return sc_core::sc_time::from_value(v);
  return kOnePs * static_cast<double>(v);
}

// Sets up a READ payload of `bytes` at `addr` (no data buffer: the traversal reads the memory
// image itself; the memory system models time only).
inline void init_read(tlm::tlm_generic_payload& p, uint64_t addr, uint32_t bytes) {
  p.set_command(tlm::TLM_READ_COMMAND);
  p.set_address(addr);
  p.set_data_ptr(nullptr);
  p.set_data_length(bytes);
  p.set_streaming_width(bytes);
  p.set_byte_enable_ptr(nullptr);
  p.set_dmi_allowed(false);
  p.set_response_status(tlm::TLM_INCOMPLETE_RESPONSE);
}

}  // namespace rtusim
