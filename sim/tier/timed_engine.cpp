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
  auto l1_timing = [](L1Timing& t, const L1Params& p) {
    t.hit_cycles = p.hit_cycles;
    t.line_size = FastDivider(p.cache.line_bytes);
    t.mshr_line.assign(p.mshrs, ~uint64_t{0});
    t.mshr_fill.assign(p.mshrs, 0);
  };
  l1_timing(node_l1_, timing.node_l1);
  if (timing.data_cache) {
    data_cache_ = std::make_unique<L1Timing>();
    l1_timing(*data_cache_, *timing.data_cache);
  }
}

TimedEngine::~TimedEngine() = default;

uint64_t TimedEngine::dram_read(uint64_t addr, uint32_t bytes, Stream s, uint64_t t) {
  // Decided at once: the queue holds this read only, so it goes when its bank is ready.
  const DramRequest r{0, addr, bytes, t * period_ps_, s};
  return cycles_.div_up(fr_fcfs_ ? fr_fcfs_->read_now(r) : dram_->read_now(r));
}

uint64_t TimedEngine::l1_miss(L1Timing& l1, uint64_t line, Stream s, uint64_t c) {
  // The first free MSHR; with none the port waits for the earliest fill.
  const size_t mshrs = l1.mshr_fill.size();
  size_t m = 0;
  while (m < mshrs && l1.mshr_fill[m] > c) ++m;
  if (m == mshrs) {
    m = static_cast<size_t>(std::min_element(l1.mshr_fill.begin(), l1.mshr_fill.end()) -
                            l1.mshr_fill.begin());
    l1.stall_cycles += l1.mshr_fill[m] - c;
    c = l1.mshr_fill[m];
    l1.port_free = c + 1;
  }
  ++l1.primary;
  l1.mshr_line[m] = line;
  l1.line_filter = 0;
  for (const uint64_t l : l1.mshr_line) l1.line_filter |= uint64_t{1} << (l & 63);
  const uint64_t line_bytes = l1.line_size.divisor();
  const uint64_t fill = dram_read(line * line_bytes, static_cast<uint32_t>(line_bytes), s,
                                  c + l1.hit_cycles);
  l1.mshr_fill[m] = fill;
  l1.busy_until = std::max(l1.busy_until, fill);
  return fill;
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
    for (uint64_t line = first; line <= last; ++line)
      ready = std::max(ready, dram_read(line * line_bytes, static_cast<uint32_t>(line_bytes),
                                        stream, t));
    return ready;
  }
  if (first == last) {  // one line: it was in the tags when it caused no DRAM bytes
    const uint64_t bytes = sink.fetch(stream, f.addr, f.bytes);
    slot.dram_bytes += bytes;
    return l1_line(*l1, first, bytes == 0, stream, t);
  }
  const SetAssocCache& tags = node ? caches.node_l1() : *caches.data_cache();
  for (uint64_t line = first; line <= last; ++line)
    ready = std::max(ready, l1_line(*l1, line, tags.contains(line * line_bytes), stream, t));
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
  return l1_line(node_l1_, line, bytes == 0, Stream::kNode, t);
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
  uint32_t slot;
  uint64_t t;
  while (events.take(slot, t)) {
    Slot& s = slots_[slot];
    if (s.phase == Phase::kStep) [[likely]] {
      const uint64_t c = std::max(t, step_free_);  // the step pipeline: one step a cycle
      step_free_ = c + 1;
      if (s.next == s.end) [[unlikely]] {  // not reached: rays end after their leaf
        if (!finish(slot, c)) return;
        continue;
      }
      const RayStepLog::Fetch node = RayStepLog::next(s.next);
      const uint64_t decided = send_node(s, node, c, sink, caches) + unit_.step_cycles;
      if (node.kind == RayStepLog::Kind::kLeaf) s.phase = Phase::kLeafBody;
      events.set(slot, decided);
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
          events.set(slot, ready);
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
          events.set(slot, ready);
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
