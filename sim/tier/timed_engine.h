// The timed interleaved mode's model of the unit (TimedInterleaver runs one or several): the
// rays in flight take their traversal steps in the order of a cheap, SystemC-free model of the
// unit's timing, not in strict turns, so rays whose nodes hit overtake rays that wait for DRAM
// as in the cycle tier. The caches' hit/miss state and byte counts stay the functional tier's
// (FetchCache); the model only decides the order of the accesses and when each ray finishes,
// but for one thing: a miss it merges into an outstanding read of its line (the tags had lost
// the line meanwhile) costs no DRAM bytes, as in the unit's L1 (DRAM bytes = primary misses).
//
// The model, in cycles of the unit's clock, from the cycle tier's own keys (CycleParams):
//  - each ray in flight has a next event (cycle, slot); the earliest goes first (ties: events
//    set kFarCycles or more ahead first, then by slot, EventWheel's order);
//  - a traversal step takes the step pipeline's next free cycle (one step per cycle), looks
//    its node's lines up in the node L1 (one lookup per cycle), is decided step_cycles after the
//    last line is in; a leaf then reads its list, then its triangles, then tests them in the
//    intersection lanes (isect.lanes, .interval_cycles, .latency_cycles), as the unit does;
//  - an L1 line (node L1, and the data cache when dcache.enable), looked up at cycle c on the
//    L1's one in-order lookup port: a line with a busy MSHR merges and waits for its fill; a
//    line in the tags answers hit_cycles later; else a free MSHR sends the line read to DRAM
//    hit_cycles later and the fill answers it; with none free the port waits for the earliest
//    fill (nothing looks up meanwhile), as the cycle tier's L1Cache does;
//  - DRAM: the configured timing model (dram.backend) through its queue, as the cycle tier's
//    Dram module drives it: a read is enqueued with its arrival time, the model decides at its
//    next decision time (FR-FCFS: the oldest row hit first), and the fill is the completion
//    rounded up to the clock. The slots' events and the DRAM's decisions go in time order (an
//    event of the decision's time first). A read's fill is unknown until it is decided: the rays
//    that wait for it have no event meanwhile, and an L1 lookup whose outcome an unknown fill may
//    change (a merge with an undecided MSHR, a miss with no MSHR known to be free) is held, with
//    the lookups behind it on that port, until the DRAM has decided far enough. Lists and
//    triangles straight to DRAM (no data cache) are read through the queue as well.
// Not modelled: the L1's fill port (one fill per cycle), its in-order port across rays of the
// same cycle, the step pipeline's booking ahead of time. estimate.cycles (the last ray's end) is
// therefore an estimate of the cycle tier's sim.cycles, not a cycle count.
// A ray's traversal does not depend on the order, so a batch's rays are traversed first
// (RayStepLog) and the model goes over their records.
//
// What it reports is a window of the batch: from the moment a given ray of it starts (the
// first: the batch's start) to the moment its rays run out (the next ray would start; rays are
// still in flight) or, for the batch's last window, to the end of its last ray. Within the
// window the caches' counters grow and every fetch's DRAM bytes are charged to its ray's pixel
// (a ray in flight at a window's edge is charged its fetches inside the window); the rays
// before it warm the model and the caches unmeasured.
#pragma once
#include <algorithm>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <span>
#include <variant>
#include <vector>

#include "cache/fetch_cache.h"
#include "layout/memory_image.h"
#include "mem/dram/dram_backend.h"
#include "mem/dram/fr_fcfs_dram.h"
#include "mem/fast_divider.h"
#include "model/cycle_params.h"
#include "model/isect_lanes.h"
#include "traversal/ray_step_log.h"
#include "tier/slot_event_tree.h"
#include "tier/slot_event_wheel.h"

namespace rtusim {

class TimedEngine {
 public:
  // Takes (pixel, DRAM bytes) of a ray's fetches.
  using Charge = std::function<void(uint32_t, uint64_t)>;
  // What a window measured.
  struct Window {
    uint64_t cycles = 0;                 // from its start to its end
    FetchCache::Counters counters{};     // the caches' counters' growth
    uint64_t primary_misses = 0, merged_misses = 0, mshr_stall_cycles = 0;  // the node L1's
  };

  // `timing` derived (CycleParams::derive()).
  TimedEngine(const CycleParams& timing, int rays_in_flight);
  ~TimedEngine();

  // Starts a batch when the previous one's rays have ended. Its window starts when its ray
  // `measure_from` (counted from 0 over the batch's logs) starts; with `stop_at_end` it ends
  // when the batch's rays run out, else when every ray has ended.
  void begin_batch(size_t measure_from, bool stop_at_end);
  // Times the batch's next log of rays through `caches` from where the previous log left off;
  // `last`: the batch's last log.
  void time(const RayStepLog& log, bool last, FetchCache& caches, const Charge& charge);
  // The batch's window, once its last log is timed.
  const Window& window() const { return window_; }

 private:
  enum class Phase : uint8_t { kStep, kLeafBody, kTriangles, kIsect };
  struct Slot {
    // The ray's steps (RayStepLog): read in its log while that is timed; what is left of them
    // is copied into `words` when the log's timing stops (the next log may reuse its memory).
    std::vector<uint64_t> words;
    const uint64_t* next = nullptr;  // the next fetch's first word
    const uint64_t* end = nullptr;
    bool in_log = false;  // next and end point into the log, not into words
    uint32_t pixel = 0;
    uint32_t tests = 0;           // of the current leaf
    Phase phase = Phase::kStep;
    uint64_t dram_bytes = 0;      // of the current ray in the window, charged when it ends
    // What its current event's sends wait for: answers (fills) not known yet, the latest
    // answer known, and the cycles its next event comes after the last answer.
    uint32_t waits = 0;
    uint32_t then_cycles = 0;
    uint64_t ready_cycle = 0;
  };
  // A fill's cycle not known yet (its read is not decided): later than every cycle.
  static constexpr uint64_t kUnknown = ~uint64_t{0};
  // An L1 lookup's answer when its slot waits for a fill not known yet (a real answer is >= 1).
  static constexpr uint64_t kWaits = 0;
  // A DRAM read's id: the MSHR index for the node L1, with kDataRead for the data cache; a read
  // straight to DRAM is kDirectRead | slot.
  static constexpr uint64_t kDataRead = uint64_t{1} << 32, kDirectRead = uint64_t{2} << 32;
  // A lookup of `line` (in the tags: `in_tags`) for `slot`'s ray at cycle t held back, with the
  // port: its outcome depends on a fill not known yet. blocked_at: the cycle it found every
  // MSHR busy (it takes the first fill), or kUnknown.
  struct Lookup {
    uint64_t line, t, blocked_at;
    uint32_t slot;
    bool in_tags;
    Stream stream;
  };
  // One L1's timing: MSHRs (line, fill cycle, the slots waiting for the fill) and the lookup
  // port.
  struct L1Timing {
    uint32_t hit_cycles = 1;
    uint64_t read_id = 0;       // its DRAM reads' ids: read_id | MSHR index
    FastDivider line_size{64};  // byte address to line number
    std::vector<uint64_t> mshr_line;  // per MSHR: its line
    std::vector<uint64_t> mshr_fill;  // per MSHR: its fill's cycle (busy before it), kUnknown
    std::vector<std::vector<uint32_t>> mshr_waiters;  // per MSHR: the slots an unknown fill holds
    uint32_t undecided = 0;   // MSHRs whose fill is unknown
    std::deque<Lookup> held;  // lookups held back, in port order (non-empty: the port waits)
    // The first held lookup stays held until the DRAM's next decision reaches this cycle or a
    // fill of this L1 becomes known (then 0).
    uint64_t held_until = 0;
    uint64_t port_free_cycle = 0;
    uint64_t busy_until_cycle = 0;  // the latest fill: no MSHR is busy from here on (kUnknown: unknown)
    uint64_t line_filter = ~uint64_t{0};  // bit (line mod 64) of every MSHR's line, or more
    uint64_t primary = 0, merged = 0, stall_cycles = 0;
  };
  // Copies the steps left of each ray that reads them in its log into the ray's slot.
  void detach_from_log();
  // time() through the concrete sink and event queue: until a slot needs a ray after the log's
  // last, or, when `last`, until the window ends.
  template <class Sink, class Events>
  void run(const RayStepLog& log, bool last, Sink& sink, Events& events, FetchCache& caches,
           const Charge& charge);
  // The window starts at cycle t / ends at cycle t (charging the rays in flight their bytes).
  void open_window(uint64_t t, const FetchCache& caches);
  void close_window(uint64_t t, const FetchCache& caches, const Charge& charge);
  // Sends fetch `f` of `slot`'s ray at cycle t: to the functional caches through `sink` (their
  // state and counts; its DRAM bytes charged to the ray) and through the timing model; returns
  // the cycle its data is all there as far as known (the slot's waits count what is not).
  template <class Sink>
  uint64_t send(Slot& slot, const RayStepLog::Fetch& f, uint64_t t, Sink& sink,
                const FetchCache& caches);
  // send() of a node fetch, its one-line case inlined.
  template <class Sink>
  [[gnu::always_inline]] inline uint64_t send_node(Slot& slot, const RayStepLog::Fetch& f,
                                                   uint64_t t, Sink& sink,
                                                   const FetchCache& caches);
  // The cycle line number `line` (in the tags before the access: `in_tags`) looked up in `l1`
  // for `slot` from cycle t is there, or kWaits (the slot's waits count it).
  [[gnu::always_inline]] uint64_t l1_line(L1Timing& l1, Slot& slot, uint64_t line,
                                          bool in_tags, Stream s, uint64_t t) {
    if (l1.held.empty()) [[likely]] {
      // A hit no MSHR can hold (no MSHR's line has its bit): no fill, known or not, changes it.
      const uint64_t c = std::max(t, l1.port_free_cycle);
      if (in_tags && (c >= l1.busy_until_cycle || !(l1.line_filter >> (line & 63) & 1))) [[likely]] {
        l1.port_free_cycle = c + 1;
        return c + l1.hit_cycles;
      }
    }
    return l1_lookup(l1, slot, line, in_tags, s, t);
  }
  // l1_line() past its common hit: a lookup that may merge, miss or wait behind held ones.
  uint64_t l1_lookup(L1Timing& l1, Slot& slot, uint64_t line, bool in_tags, Stream s, uint64_t t);
  // Decides lookup `q` (the first held, or none is) if no unknown fill can change its outcome:
  // false when one can; else true and `answer` its cycle or kWaits (q.slot waits for an MSHR's
  // fill). A primary miss sends its line read to DRAM.
  bool decide_lookup(L1Timing& l1, Lookup& q, uint64_t& answer);
  // Sends a read of `bytes` at `addr` arriving at cycle t to the DRAM's queue.
  void dram_enqueue(uint64_t id, uint64_t addr, uint32_t bytes, Stream s, uint64_t t);
  // `f` called with the DRAM model: the default one through its concrete type (no virtual call).
  template <class F>
  decltype(auto) with_dram(F&& f) {
    return fr_fcfs_ ? f(*fr_fcfs_) : f(*dram_);
  }
  // The DRAM's next decision (decision_ps_, decision_cycle_) after its queue changed.
  void note_decision();
  // Makes the DRAM's decisions due at decision_ps_: sets the fills they give, answers the slots
  // that wait for them, then decides what the held lookups can.
  template <class Events>
  void dram_decide(Events& events);
  // dram_decide() for `l1`'s held lookups (some), in port order.
  template <class Events>
  void decide_held(Events& events, L1Timing& l1);
  // `slot` gets answer `cycle` for one of its waits; the last sets its next event.
  template <class Events>
  void answer(Events& events, uint32_t slot, uint64_t cycle);
  // `slot`'s sends of this event are done: its next event at `ready` (its answers known so far)
  // + `then_cycles`, or when its last wait is answered.
  template <class Events>
  [[gnu::always_inline]] inline void await(Events& events, uint32_t slot, uint64_t ready,
                                           uint32_t then_cycles);

  UnitParams unit_;
  uint64_t period_ps_;
  FastDivider cycles_;     // ps to cycles: div_up(ps) is the first cycle boundary at or after
  FastDivider data_line_;  // lists and triangles straight to DRAM: its bursts
  int node_line_shift_;    // log2 of the node L1's line bytes (a power of two)
  L1Timing node_l1_;
  std::unique_ptr<L1Timing> data_cache_;  // nullptr: lists and triangles straight to DRAM
  std::unique_ptr<DramBackend> dram_;
  FrFcfsDram* fr_fcfs_;  // dram_ when it is the default model: called without a virtual call
  uint64_t decision_ps_ = DramBackend::kNever;  // the DRAM's next decision
  uint64_t decision_cycle_ = kUnknown;  // the last cycle at or before it (kUnknown: never)
  std::vector<DramCompletion> done_;  // scratch: a decision's completions
  std::vector<Slot> slots_;
  FetchCache* caches_ = nullptr;  // the caches of the log being timed (merged misses' refunds)
  // Each busy slot's next event, in EventWheel's order: a wheel up to 128 slots, else the tree.
  std::variant<SlotEventWheel<1>, SlotEventWheel<2>, SlotEventTree> events_;
  uint64_t step_free_ = 0;           // the step pipeline's next free cycle
  IsectLanes lanes_;
  uint64_t last_cycle_ = 0;          // the last ray's end so far
  // Where the batch's timing stopped for the next log: slots not started yet (from
  // starting_ on, at batch_start_), and a slot whose ray ended waiting for its next ray.
  static constexpr uint32_t kNoSlot = ~uint32_t{0};
  uint32_t starting_ = 0;
  uint64_t batch_start_ = 0;
  uint32_t waiting_ = kNoSlot;
  uint64_t waiting_cycle_ = 0;
  // The window: the ray it starts with (counted over the batch), whether it ends when the rays
  // run out, rays taken so far, its state and what it measured.
  size_t measure_from_ = 0;
  bool stop_at_end_ = false;
  size_t taken_ = 0;
  bool measuring_ = false, stopped_ = false;
  uint64_t window_start_ = 0;
  FetchCache::Counters counters_at_start_{};
  uint64_t primary_at_start_ = 0, merged_at_start_ = 0, stall_at_start_ = 0;
  Window window_;
};

}  // namespace rtusim
