// The timed interleaved mode's model of the unit (see timed_engine.h).
#include "tier/timed_engine.h"

#include <algorithm>
#include <bit>
#include <stdexcept>

#include "layout/layout_dispatch.h"
#include "mem/dram/dram_backends.h"

namespace rtusim {

namespace {

// The event queue for `slots` ray slots: the cheapest that holds them.
std::variant<SlotEventWheel<1>, SlotEventWheel<2>, SlotEventTree> make_events(uint32_t slots) {
  if (slots <= SlotEventWheel<1>::kMaxSlots) return SlotEventWheel<1>(slots);
  if (slots <= SlotEventWheel<2>::kMaxSlots) return SlotEventWheel<2>(slots);
  return SlotEventTree(slots);
}

}  // namespace

TimedEngine::TimedEngine(const CycleParams& timing, int rays_in_flight)
    : unit_(timing.unit),
      period_ps_(timing.unit.clock_period_ps),
      cycles_(period_ps_ ? period_ps_ : 1),
      data_line_(timing.unit.data_line_bytes),
      node_line_shift_(std::countr_zero(timing.node_l1.cache.line_bytes)),
      dram_(make_dram_backend(timing.dram)),
      fr_fcfs_(dynamic_cast<FrFcfsDram*>(dram_.get())),
      slots_(static_cast<size_t>(rays_in_flight)),
      events_(make_events(static_cast<uint32_t>(rays_in_flight))),
      lanes_(timing.unit) {
  if (period_ps_ == 0) throw std::logic_error("timed engine: clock period not derived");
  auto l1_timing = [](L1Timing& t, const L1Params& p, uint64_t read_id) {
    t.hit_cycles = p.hit_cycles;
    t.read_id = read_id;
    t.line_size = FastDivider(p.cache.line_bytes);
    t.mshr_line.assign(p.mshrs, ~uint64_t{0});
    t.mshr_fill.assign(p.mshrs, 0);
    t.mshr_waiters.resize(p.mshrs);
  };
  l1_timing(node_l1_, timing.node_l1, 0);
  if (timing.data_cache) {
    data_cache_ = std::make_unique<L1Timing>();
    l1_timing(*data_cache_, *timing.data_cache, kDataRead);
  }
}

TimedEngine::~TimedEngine() = default;

void TimedEngine::note_decision() {
  decision_ps_ = with_dram([](auto& d) { return d.next_decision_ps(); });
  decision_cycle_ = decision_ps_ == DramBackend::kNever ? kUnknown : cycles_.div(decision_ps_);
}

void TimedEngine::dram_enqueue(uint64_t id, uint64_t addr, uint32_t bytes, Stream s, uint64_t t) {
  const DramRequest r{id, addr, bytes, t * period_ps_, s};
  // A read can only bring the next decision forward: mostly it does not.
  const uint64_t ps = with_dram([&](auto& d) {
    d.enqueue(r);
    return d.next_decision_ps();
  });
  if (ps != decision_ps_) note_decision();
}

uint64_t TimedEngine::l1_lookup(L1Timing& l1, Slot& slot, uint64_t line, bool in_tags, Stream s,
                                uint64_t t) {
  Lookup q{line, t, kUnknown, static_cast<uint32_t>(&slot - slots_.data()), in_tags, s};
  uint64_t answer = kWaits;
  // Behind held lookups, or held itself: it waits with the port.
  if (!l1.held.empty() || !decide_lookup(l1, q, answer)) l1.held.push_back(q);
  if (answer == kWaits) ++slot.waits;
  return answer;
}

bool TimedEngine::decide_lookup(L1Timing& l1, Lookup& q, uint64_t& answer) {
  const size_t mshrs = l1.mshr_fill.size();
  size_t m = mshrs;
  uint64_t c = 0;  // set on both paths below (initialised for -Og's -Wmaybe-uninitialized)
  if (q.blocked_at == kUnknown) {
    c = std::max(q.t, l1.port_free_cycle);
    // An unknown fill comes after the DRAM's next decision, so after c when c is at or before
    // it: its MSHR is busy at c.
    const bool known_busy = c <= decision_cycle_;
    // A busy MSHR that holds the line: a merge answered at its fill.
    if (c < l1.busy_until_cycle && (l1.line_filter >> (q.line & 63) & 1)) {
      size_t match = mshrs;
      for (size_t i = 0; i < mshrs; ++i) {
        if (l1.mshr_line[i] != q.line || c >= l1.mshr_fill[i]) continue;
        if (l1.mshr_fill[i] == kUnknown && !known_busy) {  // busy at c or not
          l1.held_until = c;
          return false;
        }
        match = i;
      }
      if (match != mshrs) {
        l1.port_free_cycle = c + 1;
        ++l1.merged;
        if (!q.in_tags) {  // the cache counted a miss and its DRAM bytes: DRAM reads it once
          const uint64_t bytes = l1.line_size.divisor();
          caches_->refund_merged_miss(q.stream, bytes);
          Slot& s = slots_[q.slot];
          s.dram_bytes -= std::min(s.dram_bytes, bytes);
        }
        answer = l1.mshr_fill[match];
        if (answer == kUnknown) {
          answer = kWaits;
          l1.mshr_waiters[match].push_back(q.slot);
        }
        return true;
      }
    }
    if (q.in_tags) {
      l1.port_free_cycle = c + 1;
      answer = c + l1.hit_cycles;
      return true;
    }
    // A primary miss: an MSHR known to be free (which one is free makes no difference to the
    // timing), else every MSHR is busy when no unknown fill can come by c.
    for (m = 0; m < mshrs && l1.mshr_fill[m] > c; ++m) {
    }
    if (m == mshrs) {
      if (l1.undecided != 0 && !known_busy) {
        l1.held_until = c;
        return false;
      }
      q.blocked_at = c;
    }
  }
  if (q.blocked_at != kUnknown) {
    // Every MSHR busy: the port waits for the first fill, once no unknown one can come first.
    m = static_cast<size_t>(std::min_element(l1.mshr_fill.begin(), l1.mshr_fill.end()) -
                            l1.mshr_fill.begin());
    c = l1.mshr_fill[m];
    if (c == kUnknown || (l1.undecided != 0 && c > decision_cycle_)) {
      l1.held_until = c;
      return false;
    }
    l1.stall_cycles += c - q.blocked_at;
  }
  l1.port_free_cycle = c + 1;
  ++l1.primary;
  l1.mshr_line[m] = q.line;
  l1.line_filter = 0;
  for (const uint64_t l : l1.mshr_line) l1.line_filter |= uint64_t{1} << (l & 63);
  l1.mshr_fill[m] = kUnknown;
  ++l1.undecided;
  l1.busy_until_cycle = kUnknown;
  l1.mshr_waiters[m].assign(1, q.slot);
  const uint64_t line_bytes = l1.line_size.divisor();
  dram_enqueue(l1.read_id | m, q.line * line_bytes, static_cast<uint32_t>(line_bytes), q.stream,
               c + l1.hit_cycles);
  answer = kWaits;
  return true;
}

template <class Events>
void TimedEngine::answer(Events& events, uint32_t slot, uint64_t cycle) {
  Slot& s = slots_[slot];
  s.ready_cycle = std::max(s.ready_cycle, cycle);
  if (--s.waits == 0) events.set(slot, s.ready_cycle + s.then_cycles);
}

template <class Events>
void TimedEngine::await(Events& events, uint32_t slot, uint64_t ready, uint32_t then_cycles) {
  Slot& s = slots_[slot];
  if (s.waits == 0) [[likely]] {
    events.set(slot, ready + then_cycles);
    return;
  }
  s.ready_cycle = ready;
  s.then_cycles = then_cycles;
  events.clear(slot);  // no event until its last wait is answered
}

template <class Events>
void TimedEngine::dram_decide(Events& events) {
  done_.clear();
  with_dram([&](auto& d) { d.advance(decision_ps_, done_); });
  note_decision();
  for (const DramCompletion& d : done_) {
    const uint64_t fill = cycles_.div_up(d.done_ps);
    if (d.id & kDirectRead) {
      answer(events, static_cast<uint32_t>(d.id), fill);
      continue;
    }
    L1Timing& l1 = d.id & kDataRead ? *data_cache_ : node_l1_;
    const size_t m = static_cast<uint32_t>(d.id);
    l1.mshr_fill[m] = fill;
    l1.held_until = 0;
    if (--l1.undecided == 0)
      l1.busy_until_cycle = *std::max_element(l1.mshr_fill.begin(), l1.mshr_fill.end());
    for (const uint32_t slot : l1.mshr_waiters[m]) answer(events, slot, fill);
    l1.mshr_waiters[m].clear();
  }
  // The held lookups the DRAM has now decided far enough for, in port order.
  if (!node_l1_.held.empty()) decide_held(events, node_l1_);
  if (data_cache_ && !data_cache_->held.empty()) decide_held(events, *data_cache_);
}

template <class Events>
void TimedEngine::decide_held(Events& events, L1Timing& l1) {
  if (decision_cycle_ < l1.held_until) return;  // no fill known since, the DRAM not far enough
  uint64_t a = kWaits;
  while (!l1.held.empty() && decide_lookup(l1, l1.held.front(), a)) {
    const uint32_t slot = l1.held.front().slot;
    l1.held.pop_front();
    if (a != kWaits) answer(events, slot, a);
  }
}

template <class Sink>
uint64_t TimedEngine::send(Slot& slot, const RayStepLog::Fetch& f, uint64_t t, Sink& sink,
                           const FetchCache& caches) {
  const Stream stream = f.stream();
  // The access itself (the caches' state and counts) charges the ray the DRAM bytes it caused.
  if (f.bytes == 0) {
    sink.fetch(stream, f.addr, f.bytes);
    return t;
  }
  const bool node = stream == Stream::kNode;
  L1Timing* l1 = node ? &node_l1_ : data_cache_.get();
  const FastDivider& size = l1 ? l1->line_size : data_line_;
  const uint64_t line_bytes = size.divisor();
  const uint64_t first = size.div(f.addr), last = size.div(f.addr + f.bytes - 1);
  uint64_t ready = t;
  if (!l1) {  // straight to DRAM: one request per line touched, as the unit sends them
    slot.dram_bytes += sink.fetch_to_dram(stream, f.addr, f.bytes);
    const uint64_t id = kDirectRead | static_cast<uint64_t>(&slot - slots_.data());
    for (uint64_t line = first; line <= last; ++line) {
      dram_enqueue(id, line * line_bytes, static_cast<uint32_t>(line_bytes), stream, t);
      ++slot.waits;
    }
    return ready;
  }
  if (first == last) {  // one line: it was in the tags when it caused no DRAM bytes
    const uint64_t bytes = sink.fetch(stream, f.addr, f.bytes);
    slot.dram_bytes += bytes;
    return l1_line(*l1, slot, first, bytes == 0, stream, t);
  }
  const SetAssocCache& tags = node ? caches.node_l1() : *caches.data_cache();
  for (uint64_t line = first; line <= last; ++line)
    ready = std::max(ready,
                     l1_line(*l1, slot, line, tags.contains(line * line_bytes), stream, t));
  slot.dram_bytes += sink.fetch(stream, f.addr, f.bytes);
  return ready;
}

template <class Sink>
uint64_t TimedEngine::send_node(Slot& slot, const RayStepLog::Fetch& f, uint64_t t,
                                Sink& sink, const FetchCache& caches) {
  const uint64_t line = f.addr >> node_line_shift_;
  if (f.bytes == 0 || (f.addr + f.bytes - 1) >> node_line_shift_ != line) [[unlikely]]
    return send(slot, f, t, sink, caches);
  // One line: it was in the tags when it caused no DRAM bytes.
  const uint64_t bytes = sink.fetch_node_line(f.addr);
  slot.dram_bytes += bytes;
  return l1_line(node_l1_, slot, line, bytes == 0, Stream::kNode, t);
}

void TimedEngine::begin_batch(size_t measure_from, bool stop_at_end) {
  starting_ = 0;
  batch_start_ = last_cycle_;
  waiting_ = kNoSlot;
  measure_from_ = measure_from;
  stop_at_end_ = stop_at_end;
  taken_ = 0;
  measuring_ = stopped_ = false;
  window_ = Window{};
}

void TimedEngine::open_window(uint64_t t, const FetchCache& caches) {
  measuring_ = true;
  window_start_ = t;
  counters_at_start_ = caches.counters();
  primary_at_start_ = node_l1_.primary;
  merged_at_start_ = node_l1_.merged;
  stall_at_start_ = node_l1_.stall_cycles;
  for (Slot& s : slots_) s.dram_bytes = 0;  // the rays in flight: from here on
}

void TimedEngine::close_window(uint64_t t, const FetchCache& caches, const Charge& charge) {
  if (!measuring_) open_window(t, caches);  // no ray of the window started: empty
  for (Slot& s : slots_)
    if (s.dram_bytes != 0) charge(s.pixel, s.dram_bytes);  // in flight (ended rays hold 0)
  measuring_ = false;
  window_.cycles = t - window_start_;
  const FetchCache::Counters& now = caches.counters();
  for (int i = 0; i < FetchCache::kStreams; ++i)
    window_.counters[i] = now[i] - counters_at_start_[i];
  window_.primary_misses = node_l1_.primary - primary_at_start_;
  window_.merged_misses = node_l1_.merged - merged_at_start_;
  window_.mshr_stall_cycles = node_l1_.stall_cycles - stall_at_start_;
}

void TimedEngine::time(const RayStepLog& log, bool last, FetchCache& caches,
                       const Charge& charge) {
  caches_ = &caches;
  caches.with_inlined_node_l1([&](auto& sink) {
    std::visit([&](auto& events) { run(log, last, sink, events, caches, charge); }, events_);
  });
  detach_from_log();
  if (last && !stopped_) close_window(last_cycle_, caches, charge);  // every ray has ended
}

void TimedEngine::detach_from_log() {
  for (Slot& s : slots_) {
    if (!s.in_log) continue;
    s.words.assign(s.next, s.end);
    s.next = s.words.data();
    s.end = s.next + s.words.size();
    s.in_log = false;
  }
}

template <class Sink, class Events>
void TimedEngine::run(const RayStepLog& log, bool last, Sink& sink, Events& events,
                      FetchCache& caches, const Charge& charge) {
  size_t next = 0;
  // Starts the log's next ray that takes a step in `slot` at cycle t; false when the log has
  // none left and the batch goes on in the next log.
  auto start = [&](uint32_t slot, uint64_t t) {
    while (next < log.ray_count()) {
      if (!measuring_ && taken_ == measure_from_) open_window(t, caches);
      ++taken_;
      const std::span<const uint64_t> words = log.ray(next);
      const uint32_t pixel = log.pixel(next++);
      if (words.empty()) continue;  // misses the scene's bounds: no step at all
      Slot& s = slots_[slot];
      s.next = words.data();
      s.end = s.next + words.size();
      s.in_log = true;
      s.pixel = pixel;
      s.phase = Phase::kStep;
      s.dram_bytes = 0;
      events.set(slot, t);
      return true;
    }
    events.clear(slot);
    if (last && stop_at_end_) {  // the batch's rays have run out: the window ends here
      close_window(t, caches, charge);
      stopped_ = true;
      return false;
    }
    return last;
  };
  // The ray in `slot` ends at cycle t: false when its slot waits for the next log or the
  // window has ended.
  auto finish = [&](uint32_t slot, uint64_t t) {
    Slot& s = slots_[slot];
    if (measuring_) charge(s.pixel, s.dram_bytes);
    s.dram_bytes = 0;
    last_cycle_ = std::max(last_cycle_, t);
    if (start(slot, t)) return true;
    if (stopped_) return false;
    waiting_ = slot;
    waiting_cycle_ = t;
    return false;
  };
  for (; starting_ < slots_.size(); ++starting_)
    if (!start(starting_, batch_start_)) return;
  if (waiting_ != kNoSlot) {
    if (!start(waiting_, waiting_cycle_)) return;
    waiting_ = kNoSlot;
  }
  uint32_t slot = 0;  // set by take() (initialised for -Og's -Wmaybe-uninitialized)
  uint64_t t = 0;
  for (;;) {
    // The earlier of the next event and the DRAM's next decision (an event of its time first).
    if (!events.take(slot, t, decision_cycle_)) {
      if (decision_ps_ == DramBackend::kNever) break;  // neither
      dram_decide(events);
      continue;
    }
    Slot& s = slots_[slot];
    if (s.phase == Phase::kStep) [[likely]] {
      const uint64_t c = std::max(t, step_free_);  // the step pipeline: one step a cycle
      step_free_ = c + 1;
      if (s.next == s.end) [[unlikely]] {  // not reached: rays end after their leaf
        if (!finish(slot, c)) return;
        continue;
      }
      const RayStepLog::Fetch node = RayStepLog::next(s.next);
      const uint64_t in = send_node(s, node, c, sink, caches);  // decided step_cycles after
      if (node.kind == RayStepLog::Kind::kLeaf) s.phase = Phase::kLeafBody;
      await(events, slot, in, unit_.step_cycles);
      continue;
    }
    uint64_t ready;
    switch (s.phase) {
      case Phase::kStep:  // above
        break;
      case Phase::kLeafBody:
        if (s.next != s.end && RayStepLog::kind(*s.next) == RayStepLog::Kind::kList) {
          ready = send(s, RayStepLog::next(s.next), t, sink, caches);
          s.phase = Phase::kTriangles;
          await(events, slot, ready, 0);
          break;
        }
        [[fallthrough]];
      case Phase::kTriangles:
        // The rest of the leaf's fetches, all sent at once; each is a test in the lanes.
        ready = t;
        s.tests = 0;
        while (s.next != s.end && !RayStepLog::is_node(*s.next)) {
          ready = std::max(ready, send(s, RayStepLog::next(s.next), t, sink, caches));
          ++s.tests;
        }
        if (s.tests > 0) {
          s.phase = Phase::kIsect;
          await(events, slot, ready, 0);
          break;
        }
        [[fallthrough]];  // an empty leaf
      case Phase::kIsect: {
        const uint64_t done = lanes_.book(s.tests, t);
        if (s.next == s.end) {
          if (!finish(slot, done)) return;
        } else {
          s.phase = Phase::kStep;
          events.set(slot, done);
        }
        break;
      }
    }
  }
}

}  // namespace rtusim
