// The traversal unit: a pool of rays in flight (like the T&I Engine's ray accumulation unit),
// each advanced by the shared traversal_step(), with the time its fetches and tests take.
// A ray's steps do not depend on their timing, so a ray's traversal is recorded whole when it
// starts (RayStepLog: one ray in one go, which the host runs much faster than steps interleaved
// with the other rays' in flight) and its steps are then taken from the record.
//
// Per ray, one step: the traversal pipeline (one step issued per cycle) takes the ray's next
// recorded step (its node fetch; a leaf's list and triangle fetches); the node fetch goes to the
// node L1 at once; when the node is there the step takes step_cycles more; an interior step
// then issues the next step; a leaf reads its primitive list (if it has one, after
// step_cycles), then all its triangles at once (each line of each triangle one request), then
// tests them in the intersection pipeline (lanes, each accepting a test every interval_cycles,
// a result latency cycles later). A ray waiting for memory holds only its slot; the others go
// on. A finished ray frees its slot for the next ray of the batch at the same cycle.
//
// Simulation: one SC_THREAD runs an event queue of (time, ray) in time order, temporally
// decoupled: it processes events without yielding until the next one is at or after the memory
// horizon (the DRAM's next scheduling decision), then waits for the kernel to reach it. Memory
// responses arrive by direct call (DirectInitiator) or as annotated BEGIN_RESP calls (the RTL
// L1); a ray whose data is all there is queued by
// (data cycle, slot) and taken in that order, before the events of the same cycle, so steps are
// booked in time order whatever order the memory side happened to announce them in (the C++ and
// the RTL L1 announce at different moments and must give identical runs). When every memory
// component can be driven by call (the C++ L1s and the DRAM: MemoryHorizon::call_driven()), the
// unit does not wait for the kernel at a horizon but makes the components act there itself,
// and the kernel only catches up at the end of the batch: no context switch per DRAM decision.
// With the RTL L1, which runs on the kernel's clock, the kernel gets there. Reads to a C++ L1
// and to the DRAM (lists, triangles) go by direct call in picoseconds (DirectTarget,
// mem_protocol.h), not through the socket: the same decisions without sc_time arithmetic per
// request.
#pragma once
#include <algorithm>
#include <cstdint>
#include <deque>
#include <exception>
#include <string>
#include <utility>
#include <vector>

#include <systemc>
#include <tlm>
#include <tlm_utils/simple_initiator_socket.h>

#include "layout/memory_image.h"
#include "mem/fast_divider.h"
#include "mem/mem_protocol.h"
#include "model/unit_queue.h"
#include "model/host_interface.h"
#include "model/isect_lanes.h"
#include "model/unit_params.h"
#include "traversal/ray_step_log.h"
#include "traversal/fetch_recorder.h"
#include "traversal/traversal.h"

namespace rtusim {

class L1Cache;
class VcdWriter;

class Stats;


class TraversalUnit : public sc_core::sc_module, public DirectInitiator {
 public:
  tlm_utils::simple_initiator_socket<TraversalUnit> node_socket;  // to the node L1
  tlm_utils::simple_initiator_socket<TraversalUnit> data_socket;  // lists + triangles

  TraversalUnit(const sc_core::sc_module_name& name, const UnitParams& p,
                const MemoryImage& image, HostInterface& host);

  SC_HAS_PROCESS(TraversalUnit);

  // A memory component whose own activity bounds the unit's run-ahead. A component that reports
  // changes keeps a pointer to the unit's flag: it must not act once the unit is destroyed.
  void add_horizon(const MemoryHorizon* h) {
    horizons_.push_back(h);
    if (const uint64_t* w = h->horizon_word())
      horizon_words_.push_back(w);
    else
      horizons_asked_.push_back(h);
    if (h->reports_changes())
      h->watch(&horizon_moved_);
    else
      horizons_report_ = false;
  }
  // The targets bound to node_socket / data_socket, if they take reads by direct call (a C++
  // L1 for the nodes; the data cache or the DRAM for the rest); nullptr: through the socket.
  void set_direct_targets(L1Cache* node, DirectTarget* data);

  // An answer by direct call (the unit's reads by direct call name the unit as reply_to).
  void answered(tlm::tlm_generic_payload& trans, uint64_t at_ps) override;

  uint64_t steps() const { return steps_; }
  void write_stats(Stats& stats) const;  // unit.*
  // An error the unit's thread stopped the simulation with (the kernel would report it as an
  // internal error): rethrown by the host after sc_start(). Null when there is none.
  std::exception_ptr take_error() {
    if (error_)
      sc_core::sc_report_handler::set_actions("/OSCI/SystemC", sc_core::SC_INFO, info_actions_);
    return std::exchange(error_, nullptr);
  }

  // Dumps the unit's state (rays active, steps, leaf steps, intersection tests) to `vcd` at the
  // unit's own cycle times; nullptr: none.
  void set_vcd(VcdWriter* vcd);

 private:
  // What a ray does at its next event (kStep, kLeafBody, kTriangles, kIsect) or which data it
  // waits for (kNodeWait, kListWait, kTriWait).
  // kBook: ready for a step too far ahead for the calendar; books when its time comes.
  enum class Phase : uint8_t {
    kStep, kBook, kNodeWait, kLeafBody, kListWait, kTriangles, kTriWait, kIsect
  };
  using Fetch = RecordedFetch;
  // The fields every event touches first, in one cache line; the ray's record after them.
  struct UnitPayload;
  struct alignas(64) Slot {
    bool active = false;
    bool issuing = false;
    Phase phase = Phase::kStep;
    StepKind kind = StepKind::kDone;
    uint32_t ray = 0;
    uint32_t pending = 0;        // line requests outstanding
    uint64_t ready = 0;          // latest data cycle among them
    UnitPayload* node_payload = nullptr;  // its own in node_payloads_ (no deque lookup)
    FetchList fetches;           // of the current step, in issue order
    // The ray's steps, recorded when it starts (its traversal depends on nothing the timing
    // does), the next one's first word, the end, and its hit.
    const uint64_t* next = nullptr;
    const uint64_t* end = nullptr;
    Hit hit;
    RayStepLog log;
  };

  void run();
  std::exception_ptr error_;
  sc_core::sc_actions info_actions_ = 0;  // the kernel's info actions before run() stopped it
  template <class Decoder>
  void run_batch();
  // Times inside the unit are cycles of its clock; picoseconds only at the sockets.
  template <class Decoder>
  [[gnu::always_inline]] inline void process(Slot& s, uint32_t index, uint64_t cycle);
  template <class Decoder>
  void start_ray(uint32_t slot, uint64_t cycle);
  template <class Decoder>
  void finish_ray(uint32_t slot, uint64_t cycle);
  // Books the step pipeline from `cycle` on and schedules the slot's next step there.
  // schedule_step: a call; book_step: inline (an arrival's, in the hot loop).
  void schedule_step(uint32_t slot, uint64_t cycle);
  [[gnu::always_inline]] inline void book_step(uint32_t slot, uint64_t cycle);
  // book_step() when the word of `cycle` has no free cycle from it on: from the next word.
  [[gnu::noinline]] void book_step_beyond(uint32_t slot, uint64_t cycle);
  // Clears the bookings of the words of cycles that have passed (the events being processed are
  // at or after last_cycle_).
  [[gnu::cold]] void forget_bookings();
  // All data the slot waited for is there at `cycle` (inline: one per arrival, in the hot loop).
  [[gnu::always_inline]] inline void data_ready(uint32_t slot, uint64_t cycle);
  [[gnu::always_inline]] void push(uint32_t slot, uint64_t cycle) { queue_.push_event(cycle, slot); }
  // push() at a cycle known to be at or after the event being processed (untested): a node
  // read's data cycle, an arrival's decided cycle, or a booking's, whose ready cycle is the
  // event's own, later (an arrival's decided cycle, a leaf's lanes end) or a batch's start (at
  // or after the previous batch's last event).
  [[gnu::always_inline]] void push_ahead(uint32_t slot, uint64_t cycle) {
    queue_.push_event<false>(cycle, slot);
  }
  // Issues fetches [first, last) of the slot's step at `cycle`; schedules the slot when all
  // are in.
  void issue(uint32_t slot, size_t first, size_t last, uint64_t cycle);
  // issue(slot, 0, 1, cycle) for a step's node fetch, with a fast path for the common case: one
  // line, read from the C++ node L1 by direct call.
  [[gnu::always_inline]] inline void issue_node(uint32_t slot, uint64_t cycle);
  tlm::tlm_sync_enum nb_transport_bw(tlm::tlm_generic_payload& trans, tlm::tlm_phase& phase,
                                     sc_core::sc_time& delay);
  // Inline in answered() (one per answer by direct call).
  [[gnu::always_inline]] inline void arrived(tlm::tlm_generic_payload& trans, uint64_t at_ps);
  // Throws unless the memory answered TLM_OK_RESPONSE.
  static void check_response(const tlm::tlm_generic_payload& trans) {
    if (trans.get_response_status() != tlm::TLM_OK_RESPONSE) [[unlikely]] memory_error(trans);
  }
  [[noreturn, gnu::cold]] static void memory_error(const tlm::tlm_generic_payload& trans);
  [[noreturn, gnu::cold]] static void two_steps(uint64_t cycle);
  // Inline: asked at every move of a horizon, from the run loop.
  [[gnu::always_inline]] uint64_t horizon() const {
    uint64_t h = MemoryHorizon::kNever;
    for (const uint64_t* w : horizon_words_) h = std::min(h, *w);
    for (const MemoryHorizon* m : horizons_asked_) h = std::min(h, m->horizon_ps());
    return h;
  }
  uint64_t cycle_at_or_after(uint64_t t_ps) const { return cycles_.div_up(t_ps); }
  void sample_vcd(uint64_t cycle);  // samples the VCD variables, if any

  UnitParams p_;
  uint64_t period_ps_;
  FastDivider cycles_;                   // picoseconds to cycles
  FastDivider node_line_, data_line_;    // addresses to node and data lines
  const MemoryImage& image_;
  HostInterface& host_;
  std::vector<const MemoryHorizon*> horizons_;
  // horizons_ split: those read from their horizon words, those asked by call.
  std::vector<const uint64_t*> horizon_words_;
  std::vector<const MemoryHorizon*> horizons_asked_;
  // Every horizon reports its changes (MemoryHorizon::reports_changes): the unit keeps the
  // last one it computed until a component sets horizon_moved_.
  bool horizons_report_ = true;
  bool horizon_moved_ = true;
  L1Cache* node_direct_ = nullptr;
  // node_direct_ is set, on the unit's clock (reads in cycles) and its lines are the unit's
  // node lines (every one-line read valid): issue_node()'s fast path.
  bool node_fast_ = false;
  DirectTarget* data_direct_ = nullptr;
  std::vector<CallDriven*> due_;  // scratch: components acted for at one horizon
  std::vector<Slot> slots_;
  // Events, and rays whose data is all there (arrivals: by data cycle, then slot, before the
  // events of their cycle).
  UnitQueue queue_;
  uint32_t active_ = 0;
  // The step pipeline takes one step per cycle. Bookings as a bit per cycle over a window of
  // kCalendarCycles from the current cycle (far more than any memory latency); bits behind the
  // current cycle are cleared as time passes. A step books the first free cycle from the one it
  // is ready in.
  static constexpr uint64_t kCalendarCycles = uint64_t{1} << 16;
  std::vector<uint64_t> step_calendar_;  // kCalendarCycles / 64 words
  uint64_t calendar_clear_ = 0;          // cycles before this one are cleared
  IsectLanes lanes_;

  // A payload of the unit's, with its tag at hand (get_extension() is a library call; the
  // memory side returns the very payload the unit sent).
  struct UnitPayload : tlm::tlm_generic_payload {
    FetchTag* tag = nullptr;  // owned by the payload as its extension
    bool pooled = true;       // in the free list when not in flight; else a slot's own
    UnitPayload* next_free = nullptr;  // the free list's next, while in it
  };
  std::deque<UnitPayload> payloads_;
  // The pooled payloads not in flight, last freed first: a list through next_free (freeing one
  // is two stores, no vector growth to keep out of the answer path).
  UnitPayload* free_payloads_ = nullptr;
  void free_payload(UnitPayload* p) {
    p->next_free = free_payloads_;
    free_payloads_ = p;
  }
  // Per slot, its payload for issue_node()'s one-line node read (a slot has at most one node
  // read in flight): command, length and tag set once, the address per read.
  std::deque<UnitPayload> node_payloads_;
  // A read of slot `s` answered within the call that sent it, at cycle `ready`: what arrived()
  // does, its payload free again at once.
  [[gnu::always_inline]] void completed(Slot& s, UnitPayload* p, uint64_t ready) {
    check_response(*p);
    if (p->pooled) free_payload(p);
    s.ready = std::max(s.ready, ready);
    --s.pending;
  }
  // The last entry taken from the queue (never ahead of the one being processed: the step
  // calendar forgets the words before it), and the latest end of a ray in the batch, which may
  // be later (a ray ends when its leaf's tests do): the batch ends at the later of the two.
  uint64_t last_cycle_ = 0;
  uint64_t end_cycle_ = 0;
  uint64_t last_step_cycle_ = ~uint64_t{0};  // of the last step taken (none: all ones)

  uint64_t steps_ = 0, leaf_steps_ = 0, isect_tests_ = 0, rays_ = 0;
  uint64_t stack_overflows_ = 0;
  uint64_t events_processed_ = 0, kernel_waits_ = 0;
  int max_stack_ = 0;

  VcdWriter* vcd_ = nullptr;
  uint32_t vcd_active_ = 0, vcd_steps_ = 0, vcd_leaf_steps_ = 0, vcd_isect_ = 0;
};

}  // namespace rtusim
