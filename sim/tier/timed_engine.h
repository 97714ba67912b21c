// The timed interleaved mode's model of the unit (TimedInterleaver runs one or several): the
// rays in flight take their traversal steps in the order of a cheap, SystemC-free model of the
// unit's timing, not in strict turns, so rays whose nodes hit overtake rays that wait for DRAM
// as in the cycle tier. The caches' hit/miss state and byte counts stay the functional tier's
// (FetchCache); the model only decides the order of the accesses and when each ray finishes.
//
// The model, in cycles of the unit's clock, from the cycle tier's own keys (CycleParams):
//  - each ray in flight has a next event (cycle, slot); the earliest goes first (ties: events
//    set kFarCycles or more ahead first, then by slot, EventWheel's order);
//  - a traversal step takes the step pipeline's next free cycle (one step per cycle), looks
//    its node's lines up in the node L1 (one lookup per cycle), is decided step_cycles after the
//    last line is in; a leaf then reads its list, then its triangles, then tests them in the
//    intersection lanes (isect.lanes, .interval_cycles, .latency_cycles), as the unit does;
//  - an L1 line (node L1, and the data cache when dcache.enable): a line with a busy MSHR
//    merges and waits for its fill; a line in the tags answers hit_cycles later; else a free
//    MSHR sends the line read to DRAM hit_cycles later and the fill answers it; with none free
//    the lookup port waits for the earliest fill;
//  - DRAM: the configured timing model (dram.backend, its banks, rows and bus) with each read
//    decided as soon as it is sent: first come, first served, no FR-FCFS reordering.
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
#include <functional>
#include <memory>
#include <span>
#include <variant>
#include <vector>

#include "cache/stream_caches.h"
#include "layout/memory_image.h"
#include "mem/dram/dram_backend.h"
#include "mem/dram/fr_fcfs_dram.h"
#include "mem/fast_divider.h"
#include "model/cycle_params.h"
#include "model/isect_lanes.h"
#include "tier/ray_step_log.h"
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
  };
  // One L1's timing: MSHRs (line, fill cycle) and the lookup port.
  struct L1Timing {
    uint32_t hit_cycles = 1;
    FastDivider line_size{64};  // byte address to line number
    std::vector<uint64_t> mshr_line;  // per MSHR: its line
    std::vector<uint64_t> mshr_fill;  // per MSHR: its fill's cycle (busy before it)
    uint64_t port_free = 0;
    uint64_t busy_until = 0;  // the latest fill: no MSHR is busy from here on
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
  // the cycle its data is all there.
  template <class Sink>
  uint64_t send(Slot& slot, const RayStepLog::Fetch& f, uint64_t t, Sink& sink,
                const FetchCache& caches);
  // send() of a node fetch, its one-line case inlined.
  template <class Sink>
  [[gnu::always_inline]] inline uint64_t send_node(Slot& slot, const RayStepLog::Fetch& f,
                                                   uint64_t t, Sink& sink,
                                                   const FetchCache& caches);
  // The cycle line number `line` (in the tags before the access: `in_tags`) looked up in `l1`
  // from cycle t is there.
  [[gnu::always_inline]] uint64_t l1_line(L1Timing& l1, uint64_t line, bool in_tags, Stream s,
                                          uint64_t t) {
    const uint64_t c = std::max(t, l1.port_free);
    l1.port_free = c + 1;
    // Some MSHR is busy and may hold the line: a merge answers at its pending fill.
    if (c < l1.busy_until && (l1.line_filter >> (line & 63) & 1)) {
      uint64_t merged_fill = 0;  // a busy MSHR's fill is after c >= 0: 0 is none
      for (size_t i = 0; i < l1.mshr_line.size(); ++i)
        merged_fill = c < l1.mshr_fill[i] && l1.mshr_line[i] == line ? l1.mshr_fill[i]
                                                                      : merged_fill;
      if (merged_fill) {
        ++l1.merged;
        return merged_fill;
      }
    }
    if (in_tags) [[likely]]
      return c + l1.hit_cycles;
    return l1_miss(l1, line, s, c);
  }
  // A primary miss of `line` in `l1` looked up at cycle c: the cycle its fill is there.
  uint64_t l1_miss(L1Timing& l1, uint64_t line, Stream s, uint64_t c);
  // The cycle a DRAM read of `bytes` at `addr` sent at cycle t completes.
  uint64_t dram_read(uint64_t addr, uint32_t bytes, Stream s, uint64_t t);

  UnitParams unit_;
  uint64_t period_ps_;
  FastDivider cycles_;     // ps to cycles: div_up(ps) is the first cycle boundary at or after
  FastDivider data_line_;  // lists and triangles straight to DRAM: its bursts
  int node_line_shift_;    // log2 of the node L1's line bytes (a power of two)
  L1Timing node_l1_;
  std::unique_ptr<L1Timing> data_cache_;  // nullptr: lists and triangles straight to DRAM
  std::unique_ptr<DramBackend> dram_;
  FrFcfsDram* fr_fcfs_;  // dram_ when it is the default model: its read_now without a virtual call
  std::vector<Slot> slots_;
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
