// A non-blocking read cache as a SystemC module (TLM-2.0 AT sockets, see mem_protocol.h): the
// tag store and replacement of the behavioural SetAssocCache, one lookup port, MSHRs and a fill
// port. Its cycle-level behaviour is the one the RTL node L1 (rtl_model/l1_cache.sv behind
// RtlL1Adapter) implements, so l1.model = cpp and rtl give identical counters and cycles.
//
// Times are cycles of the clock (period P); a request's time t is its payload time rounded up
// to an edge; H = hit_cycles.
//  - Lookup port: one lookup per cycle, requests in arrival order; request i looks up at cycle
//    c = max(t_i, c_{i-1} + 1). At c (state: earlier lookups, fills of cycle <= c):
//      an MSHR busy at c (allocated <= c < its fill cycle) holds the line: a merged miss,
//        answered at that fill;
//      else the line is in the tags: a hit, answered at c + H;
//      else an MSHR is free: a primary miss; the MSHR is busy from c, the line read goes
//        downstream at c + H, the answer comes at its fill;
//      else the port blocks (in order: nothing looks up meanwhile) until the earliest fill of
//        a busy MSHR, T, where the request is a primary miss; mshr_stall_cycles += T - c.
//    Every lookup but a blocked one is one SetAssocCache::access (touch, or victim + install +
//    touch: allocate on miss, merges included), so the hit/miss state is the functional tier's
//    for the same order.
//  - Fill port: the downstream completion F gives the fill cycle, the first cycle >= F (rounded
//    up to an edge) that no other fill holds, in the order the answers arrive. The MSHR is free
//    from that cycle on; every request on it is answered there.
//
// Event-driven, not clocked: a lookup at cycle c is decided as soon as no fill unknown so far
// can come at or before c, i.e. c*P is at or before the later of the kernel time and the
// downstream horizon. That holds when the downstream announces each completion before it
// happens, never decides a queued read before its horizon (other initiators' reads cannot
// pull it forward; the DRAM model's decisions are so) and keeps its horizon before every
// completion it has decided but not announced yet (the DRAM answers a batch of decisions one by
// one, and we decide lookups in the callback of each answer), and our own later reads go out
// after the lookups still to decide. A request looked up at its own time is decided on arrival and, if
// it is a hit or merges on a known fill, completes at once (TLM_COMPLETED, annotated time);
// otherwise it gets BEGIN_RESP. A backlog (several requests in one cycle, a blocked port) is
// decided by a method at its cycle (driven by call: by the initiator's call there), and the
// cache is a MemoryHorizon for the initiator meanwhile.
// Counters: hits, primary and merged misses, mshr_stall_cycles, and the mean primary miss
// latency (fill cycle - request time t: port wait and stall included).
#pragma once
#include <algorithm>
#include <cstdint>
#include <cstddef>
#include <string>
#include <vector>

#include <systemc>
#include <tlm>
#include <tlm_utils/simple_initiator_socket.h>
#include <tlm_utils/simple_target_socket.h>

#include "cache/cache_params.h"
#include "mem/l1_params.h"
#include "cache/set_assoc_cache.h"
#include "mem/fast_divider.h"
#include "mem/mem_protocol.h"
#include "mem/node_l1.h"

namespace rtusim {

class L1Cache final : public sc_core::sc_module, public NodeL1, public MemoryHorizon,
                      public CallDriven, public DirectTarget, public DirectInitiator {
 public:
  tlm_utils::simple_target_socket<L1Cache> target_socket;        // from the unit
  tlm_utils::simple_initiator_socket<L1Cache> initiator_socket;  // to DRAM

  L1Cache(const sc_core::sc_module_name& name, const L1Params& p);

  SC_HAS_PROCESS(L1Cache);

  tlm::tlm_target_socket<>& upstream() override { return target_socket; }
  tlm::tlm_initiator_socket<>& downstream() override { return initiator_socket; }
  // The downstream's next decision (the DRAM). Without one, the downstream must answer every
  // read at once (TLM_COMPLETED).
  void set_downstream_horizon(const MemoryHorizon* h) override {
    downstream_horizon_ = h;
    downstream_word_ = h ? h->horizon_word() : &kNeverWord;
  }
  // The target bound to initiator_socket, if it takes reads by direct call and answers them so
  // (the DRAM); nullptr: through the socket.
  void set_downstream_direct(DirectTarget* d) { downstream_direct_ = d; }

  uint64_t hits() const override { return hits_; }
  uint64_t primary_misses() const override { return primary_; }
  uint64_t merged_misses() const override { return merged_; }
  uint64_t mshr_stall_cycles() const override { return stall_cycles_; }
  double mean_miss_latency_cycles() const override {
    return fills_ ? double(miss_latency_cycles_) / double(fills_) : 0.0;
  }
  uint64_t bytes_from_dram() const override { return primary_ * line_bytes_; }
  const MemoryHorizon* horizon() const override { return this; }
  // The cycle of the first lookup not decided yet (the initiator must not run past it), or
  // never.
  uint64_t horizon_ps() const override { return horizon_ps_; }
  const uint64_t* horizon_word() const override { return &horizon_ps_; }
  bool reports_changes() const override { return true; }
  // A module is never a const object: the horizon view hands out the module to drive.
  CallDriven* call_driven() const override { return const_cast<L1Cache*>(this); }
  void set_driven_by_call(bool on) override {
    driven_by_call_ = on;
    if (!on) schedule_wake();  // its process takes over from here
  }
  void act_at_horizon(uint64_t) override { advance(); }
  // The upstream request by direct call (what nb_transport_fw does, in picoseconds).
  bool read_at(tlm::tlm_generic_payload& trans, uint64_t at_ps, uint64_t* done_ps) override;
  bool read_tagged_at(tlm::tlm_generic_payload& trans, const FetchTag* tag, uint64_t at_ps,
                      uint64_t* done_ps) override;
  // read_at() for an initiator on the cache's clock, in its cycles: the request at cycle t (at
  // t * clock period); true: completed, *answer_cycle the cycle of its answer. `tag`: the
  // payload's FetchTag (or nullptr if it has none), handed in so the cache need not look it up.
  // Through an L1Cache* (the class is final) one indirect call into read_cycle_as<the tags'
  // cache type>.
  bool read_cycle(tlm::tlm_generic_payload& trans, const FetchTag* tag, uint64_t t,
                  uint64_t* answer_cycle) {
    if (!valid_read(trans)) [[unlikely]] {
      *answer_cycle = t;
      return true;
    }
    return read_cycle_(*this, trans, tag, t, answer_cycle);
  }
  // read_cycle() of a read the caller knows to be valid: a READ of bytes within one line.
  bool read_line_cycle(tlm::tlm_generic_payload& trans, const FetchTag* tag, uint64_t t,
                       uint64_t* answer_cycle) {
    return read_cycle_(*this, trans, tag, t, answer_cycle);
  }
  uint64_t clock_period_ps() const { return period_ps_; }
  // A fill by direct call (the MSHRs' reads name the cache as reply_to when they go by direct
  // call).
  void answered(tlm::tlm_generic_payload& trans, uint64_t at_ps) override;
  const SetAssocCache& tags() const { return tags_; }
  const L1Params& params() const { return p_; }

 private:
  static constexpr uint64_t kUnknown = ~uint64_t{0};
  struct Request {
    tlm::tlm_generic_payload* trans;
    const FetchTag* tag;              // its FetchTag, or nullptr
    uint64_t t;                       // its time (cycle)
    uint64_t blocked_at = kUnknown;   // first cycle it was refused for want of an MSHR
  };
  // An MSHR's line and fill cycle are in mshr_line_ / mshr_fill_ at its index.
  struct Mshr {
    uint64_t request_cycle = 0;  // the primary request's time
    std::vector<Request> waiters;  // answered at the fill
    tlm::tlm_generic_payload payload;  // the line read; owns its FetchTag
    FetchTag* tag = nullptr;
  };
  enum class Outcome { kAnswered, kWaiting, kBlocked };

  tlm::tlm_sync_enum nb_transport_fw(tlm::tlm_generic_payload& trans, tlm::tlm_phase& phase,
                                     sc_core::sc_time& delay);
  tlm::tlm_sync_enum nb_transport_bw(tlm::tlm_generic_payload& trans, tlm::tlm_phase& phase,
                                     sc_core::sc_time& delay);
  // Decides queued lookups, oldest first, while they are decidable; answers them. One indirect
  // call into advance_as<the tags' cache type>, whose lookups call its access() inline.
  void advance() { advance_(*this); }
  template <class Cache>
  void advance_as();
  // Latest time (ps) up to which every fill is known: our unknown fills complete after the
  // downstream's next decision; our future reads are sent after the lookups still to decide.
  uint64_t decidable_ps() const { return std::max(now_ps(), downstream_horizon()); }
  // at_ps <= decidable_ps(), the kernel's time asked only if the downstream's horizon is before.
  bool decidable_at(uint64_t at_ps) const {
    return at_ps <= downstream_horizon() || at_ps <= now_ps();
  }
  // The downstream's horizon (kNever without one), from its horizon word if it has one.
  uint64_t downstream_horizon() const {
    return downstream_word_ ? *downstream_word_ : downstream_horizon_->horizon_ps();
  }
  // A read of one line: else the error response set.
  bool valid_read(tlm::tlm_generic_payload& trans) {
    const uint64_t addr = trans.get_address();
    const uint32_t len = trans.get_data_length();
    if (trans.get_command() != tlm::TLM_READ_COMMAND || len == 0 ||
        (addr >> offset_bits_) != ((addr + len - 1) >> offset_bits_)) [[unlikely]] {
      trans.set_response_status(tlm::TLM_GENERIC_ERROR_RESPONSE);  // one line per request
      return false;
    }
    return true;
  }
  // read_cycle() of a valid read with the tags' concrete cache `Cache` (SetAssocCache's
  // variant alternative): a lookup decidable at once calls its access() inline.
  template <class Cache>
  bool read_cycle_as(tlm::tlm_generic_payload& trans, const FetchTag* tag, uint64_t t,
                     uint64_t* answer_cycle);
  // read_cycle() of a valid read, for any state of the port and the MSHRs (tags: tags_'s
  // concrete cache).
  template <class Cache>
  bool read_general_as(Cache& tags, tlm::tlm_generic_payload& trans, const FetchTag* tag,
                       uint64_t t, uint64_t* answer_cycle);
  // The end of a read's lookup at cycle c: answered (true, the response set), waiting for a
  // pending fill, or blocked: queued, decided after the first fill.
  [[gnu::always_inline]] bool settle(Outcome o, const Request& r, uint64_t c) {
    switch (o) {
      case Outcome::kAnswered:
        r.trans->set_response_status(tlm::TLM_OK_RESPONSE);
        return true;
      case Outcome::kWaiting:
        return false;
      case Outcome::kBlocked:
        queue_push({r.trans, r.tag, r.t, c});
        schedule_wake();
        return false;
    }
    return false;
  }
  // The lookup of `r` at cycle c with the tags' concrete cache `Cache` (its access() inline);
  // kAnswered sets *answer_cycle.
  template <class Cache>
  Outcome lookup_as(Cache& tags, const Request& r, uint64_t c, uint64_t* answer_cycle);
  // The rest of a lookup that missed with MSHR `m` free (the line is now in the tags): `m`
  // reads the line downstream.
  Outcome primary_miss(const Request& r, size_t m, uint64_t line, uint64_t c,
                       uint64_t* answer_cycle);
  // Earliest fill cycle among the MSHRs (all busy); kUnknown if none is known.
  uint64_t first_fill() const;
  void fill(size_t m, uint64_t done_ps);
  // `tag`: the request's FetchTag (or nullptr); its reply_to, if any, takes the answer.
  void respond(tlm::tlm_generic_payload& trans, const FetchTag* tag, uint64_t cycle);
  // Recomputes the horizon after the lookup port's state may have changed; tells the watchers
  // if it moved. Every change that can move it (a request queued, advance()) ends in
  // schedule_wake(), which calls this; a lookup decided on arrival with nothing queued does not
  // move it (never, before and after).
  void update_horizon();
  void schedule_wake();  // the horizon updated; the method runs there, if any
  void wake();           // SC_METHOD: decides the backlog at its cycle

  L1Params p_;
  SetAssocCache tags_;
  void* tag_cache_ = nullptr;  // tags_'s concrete cache, as read_cycle_ knows its type
  // read_cycle_as and advance_as<tags_'s concrete cache>, as plain function pointers (a call
  // through a member function pointer tests and adjusts it first).
  bool (*read_cycle_)(L1Cache&, tlm::tlm_generic_payload&, const FetchTag*, uint64_t,
                      uint64_t*) = nullptr;
  void (*advance_)(L1Cache&) = nullptr;
  uint32_t offset_bits_;
  uint64_t line_bytes_;
  uint64_t period_ps_;
  FastDivider cycles_;  // picoseconds to cycles
  const MemoryHorizon* downstream_horizon_ = nullptr;
  // downstream_horizon_'s horizon word; kNeverWord without a downstream horizon; nullptr: ask it.
  static constexpr uint64_t kNeverWord = kNever;
  const uint64_t* downstream_word_ = &kNeverWord;
  DirectTarget* downstream_direct_ = nullptr;
  std::vector<Mshr> mshrs_;
  size_t mshr_count_;  // mshrs_.size() in one load (Mshr's size is no power of two)
  // Per MSHR, in arrays a lookup scans without a branch per MSHR: its line, and the cycle it is
  // busy until (kUnknown until the downstream answers; busy at c while c < it).
  std::vector<uint64_t> mshr_line_, mshr_fill_;
  uint64_t busy_until_ = 0;  // the latest fill cycle among them (kUnknown: one is not known)
  // With at most 64 MSHRs: a superset of those busy at the next lookup (set at allocation,
  // cleared by a lookup at or after the fill; lookups come in rising cycles and a fill is never
  // before the next lookup, so a cleared MSHR stays free until allocated again).
  uint64_t busy_mask_ = 0;
  // With busy_mask_: a bit per line number mod 64 of the MSHRs in busy_mask_ (a superset, set at
  // allocation, recomputed when the mask shrinks). A line whose bit is clear merges with none.
  uint64_t busy_lines_ = 0;
  // Requests not looked up yet, in arrival order: queue_[queue_head_ .. queue_end_). An array
  // taken from the front (a std::deque's push and pop are calls; a vector's push_back is one
  // too, for its growth): emptied whenever the last is taken, its taken front dropped when it
  // is most of it, grown out of line when full.
  std::vector<Request> queue_;
  size_t queue_head_ = 0, queue_end_ = 0;
  // queue_empty() in one load (a read tests it first): false from a push until the last is
  // taken.
  bool backlog_ = false;
  bool queue_empty() const { return !backlog_; }
  void queue_push(const Request& r) {
    if (queue_end_ == queue_.size()) [[unlikely]] queue_grow();
    queue_[queue_end_++] = r;
    backlog_ = true;
  }
  [[gnu::noinline, gnu::cold]] void queue_grow() { queue_.resize(2 * queue_.size() + 16); }
  Request& queue_front() { return queue_[queue_head_]; }
  const Request& queue_front() const { return queue_[queue_head_]; }
  void queue_pop() {
    if (++queue_head_ == queue_end_) {
      queue_head_ = queue_end_ = 0;
      backlog_ = false;
      stalled_ = false;
    } else if (queue_head_ >= 1024 && 2 * queue_head_ >= queue_end_) {
      std::copy(queue_.begin() + static_cast<std::ptrdiff_t>(queue_head_),
                queue_.begin() + static_cast<std::ptrdiff_t>(queue_end_), queue_.begin());
      queue_end_ -= queue_head_;
      queue_head_ = 0;
    }
  }
  // advance() stopped at the backlog's front, undecidable at decidable_ps() =
  // stalled_limit_ps_, and nothing its decision depends on but that limit has changed since
  // (the front, the port's next cycle, the MSHRs' fills): it stays so while the limit does not
  // grow.
  bool stalled_ = false;
  uint64_t stalled_limit_ps_ = 0;
  void stall(uint64_t limit_ps) {
    stalled_ = true;
    stalled_limit_ps_ = limit_ps;
  }
  uint64_t next_lookup_ = 0;      // the port's next free cycle
  uint64_t horizon_ps_ = kNever;  // as update_horizon() last found it
  sc_core::sc_event wake_;
  bool driven_by_call_ = false;  // the initiator calls act_at_horizon(): no wake-ups
  uint64_t hits_ = 0, primary_ = 0, merged_ = 0, stall_cycles_ = 0;
  uint64_t fills_ = 0, miss_latency_cycles_ = 0;
};

}  // namespace rtusim
