#include "model/traversal_unit.h"

#include <algorithm>
#include <bit>
#include <stdexcept>

#include "layout/layout_dispatch.h"
#include "mem/l1_cache.h"
#include "util/error.h"
#include "util/stat_decl.h"
#include "util/stats.h"
#include "util/vcd_writer.h"

namespace rtusim {
namespace {
// Stats keys of the SystemC traversal unit.
const StatDecl kUnitRays("unit.rays", StatKind::kCounter, "rays",
                         "rays the unit traversed");
const StatDecl kUnitSteps("unit.steps", StatKind::kCounter, "steps",
                          "traversal steps (node fetches)");
const StatDecl kUnitLeafSteps("unit.leaf_steps", StatKind::kCounter, "steps",
                              "steps at a leaf");
const StatDecl kUnitIsectTests("unit.isect_tests", StatKind::kCounter, "tests",
                               "ray-triangle tests");
const StatDecl kUnitMaxStack("unit.max_stack_depth", StatKind::kRatio, "entries",
                             "deepest traversal stack reached (a maximum)");
const StatDecl kUnitOverflow("unit.stack_overflow_steps", StatKind::kCounter, "steps",
                             "steps whose push overflowed the stack (sim.stack_depth)");
const StatDecl kUnitEvents("unit.events", StatKind::kCounter, "events",
                           "simulator effort: unit events processed");
const StatDecl kUnitKernelWaits("unit.kernel_waits", StatKind::kCounter, "waits",
                                "simulator effort: SystemC waits (memory-horizon syncs)");

const UnitParams& checked(const UnitParams& p) {
  validate(p);
  return p;
}
}  // namespace

TraversalUnit::TraversalUnit(const sc_core::sc_module_name& name, const UnitParams& p,
                             const MemoryImage& image, HostInterface& host)
    : sc_module(name),
      node_socket("node_socket"),
      data_socket("data_socket"),
      p_(checked(p)),
      period_ps_(p.clock_period_ps),
      cycles_(p.clock_period_ps),
      node_line_(p.node_line_bytes),
      data_line_(p.data_line_bytes),
      image_(image),
      host_(host),
      slots_(p.rays_in_flight),
      queue_(p.rays_in_flight),
      step_calendar_(kCalendarCycles / 64, 0),
      lanes_(p) {
  for (uint32_t i = 0; i < p.rays_in_flight; ++i) {
    UnitPayload& q = node_payloads_.emplace_back();
    q.pooled = false;
    q.tag = new FetchTag;
    q.tag->stream = Stream::kNode;
    q.tag->owner = i;
    q.tag->reply_to = this;
    q.set_extension(q.tag);
    init_read(q, 0, p.node_line_bytes);
    slots_[i].node_payload = &q;
  }
  node_socket.register_nb_transport_bw(this, &TraversalUnit::nb_transport_bw);
  data_socket.register_nb_transport_bw(this, &TraversalUnit::nb_transport_bw);
  SC_THREAD(run);
}

void TraversalUnit::set_direct_targets(L1Cache* node, DirectTarget* data) {
  node_direct_ = node;
  // On the unit's clock (reads in cycles) with the unit's node lines (every read valid).
  node_fast_ = node && node->clock_period_ps() == period_ps_ &&
               node->params().cache.line_bytes == node_line_.divisor();
  data_direct_ = data;
}

void TraversalUnit::run() {
  for (;;) {
    // A batch posted before the first sc_start() notifies before this thread waits: check.
    if (!host_.has_work()) {
      wait(host_.posted());
      continue;
    }
    try {
      with_layout_decoder(image_, [&]<class Decoder>() { run_batch<Decoder>(); });
    } catch (const sc_core::sc_unwind_exception&) {
      throw;  // the kernel's own (a process killed or reset): it must go on
    } catch (...) {  // to the host, as thrown: the kernel would wrap it as its own error
      error_ = std::current_exception();
      // Stopped quietly (take_error() puts the kernel's info messages back): the error is the
      // host's to report, in one line.
      info_actions_ = sc_core::sc_report_handler::set_actions(
          "/OSCI/SystemC", sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
      sc_core::sc_stop();
      return;
    }
  }
}

template <class Decoder>
void TraversalUnit::run_batch() {
  const uint64_t t0 = cycle_at_or_after(now_ps());
  last_cycle_ = t0;
  end_cycle_ = t0;
  const bool vcd = vcd_ != nullptr;  // in a register: the loop's stores may alias vcd_
  // When every memory component can be driven by call, the unit acts for them at their
  // horizons and the kernel only catches up at the end of the batch.
  bool by_call = !horizons_.empty();
  for (const MemoryHorizon* m : horizons_) by_call = by_call && m->call_driven();
  if (by_call)
    for (const MemoryHorizon* m : horizons_) m->call_driven()->set_driven_by_call(true);
  for (uint32_t i = 0; i < slots_.size(); ++i) start_ray<Decoder>(i, t0);
  if (vcd_) sample_vcd(t0);
  // The horizon, and the first cycle at or after it (kNever: none).
  uint64_t h = 0, h_cycle = 0;
  horizon_moved_ = true;
  while (active_ > 0) {
    if (horizon_moved_) {
      horizon_moved_ = !horizons_report_;  // asked every time unless every horizon reports
      h = horizon();
      h_cycle = h == MemoryHorizon::kNever ? ~uint64_t{0} : cycle_at_or_after(h);
    }
    // Arrivals before the events of their cycle (the queue's order); both only before the
    // horizon. Taking an arrival touches no memory component: the horizon holds.
    const uint64_t next = queue_.top_cycle();  // all ones: nothing queued
    if (next >= h_cycle) {
      // Nothing to do before the memory acts on its own: let the kernel get there.
      if (h == MemoryHorizon::kNever)
        throw std::logic_error("traversal unit: rays wait for memory that has nothing scheduled");
      ++kernel_waits_;
      if (by_call) {
        // What the kernel would run at h: every component due there (a snapshot, as the
        // kernel's timed notifications for h), in the reverse order of add_horizon(): the
        // backend adds the DRAM first, so the caches act before the DRAM they read from, the
        // order in which the kernel runs them (unit.kernel_waits, which counts these syncs, is
        // the kernel's count in every reference case).
        due_.clear();
        for (auto it = horizons_.rbegin(); it != horizons_.rend(); ++it)
          if ((*it)->horizon_ps() <= h) due_.push_back((*it)->call_driven());
        for (CallDriven* m : due_) m->act_at_horizon(h);
        continue;
      }
      const uint64_t now = now_ps();
      wait(h > now ? ps(h - now) : sc_core::SC_ZERO_TIME);
      continue;
    }
    uint64_t t;
    bool arrival;
    const uint32_t slot = queue_.pop(t, arrival);
    last_cycle_ = std::max(last_cycle_, t);
    if (arrival) {
      data_ready(slot, t);
      continue;
    }
    ++events_processed_;
    process<Decoder>(slots_[slot], slot, t);
    if (vcd) [[unlikely]] sample_vcd(t);
  }
  // The kernel catches up with the unit: the batch ends at its last event.
  if (by_call)
    for (const MemoryHorizon* m : horizons_) m->call_driven()->set_driven_by_call(false);
  const uint64_t end_ps = std::max(last_cycle_, end_cycle_) * period_ps_, now = now_ps();
  if (end_ps > now) wait(ps(end_ps - now));
}

void TraversalUnit::set_vcd(VcdWriter* vcd) {
  vcd_ = vcd;
  if (!vcd_) return;
  vcd_active_ = vcd_->add("rays_active", 32);
  vcd_steps_ = vcd_->add("steps", 64);
  vcd_leaf_steps_ = vcd_->add("leaf_steps", 64);
  vcd_isect_ = vcd_->add("isect_tests", 64);
}

void TraversalUnit::sample_vcd(uint64_t cycle) {
  const uint64_t at_ps = cycle * period_ps_;
  vcd_->sample(at_ps, vcd_active_, active_);
  vcd_->sample(at_ps, vcd_steps_, steps_);
  vcd_->sample(at_ps, vcd_leaf_steps_, leaf_steps_);
  vcd_->sample(at_ps, vcd_isect_, isect_tests_);
}

template <class Decoder>
void TraversalUnit::start_ray(uint32_t slot, uint64_t t) {
  Slot& s = slots_[slot];
  uint32_t index;
  while (host_.next(index)) {
    // The ray's whole traversal, recorded now in one go: the steps it will take.
    s.log.clear();
    s.hit = s.log.record<Decoder>(image_, host_.ray(index), [&](const TraversalState& st) {
      max_stack_ = std::max(max_stack_, st.sp);
      if (st.sp > static_cast<int>(p_.stack_depth)) ++stack_overflows_;
    });
    ++rays_;
    const std::span<const uint64_t> words = s.log.ray(0);
    if (words.empty()) {  // misses the scene's bounds: no step at all
      host_.complete(index, s.hit);
      continue;
    }
    s.next = words.data();
    s.end = s.next + words.size();
    s.active = true;
    s.ray = index;
    ++active_;
    schedule_step(slot, t);
    return;
  }
  s.active = false;
}

template <class Decoder>
void TraversalUnit::finish_ray(uint32_t slot, uint64_t t) {
  Slot& s = slots_[slot];
  host_.complete(s.ray, s.hit);
  end_cycle_ = std::max(end_cycle_, t);
  s.active = false;
  --active_;
  start_ray<Decoder>(slot, t);
}

void TraversalUnit::schedule_step(uint32_t slot, uint64_t t) { book_step(slot, t); }

void TraversalUnit::book_step(uint32_t slot, uint64_t t) {
  constexpr uint64_t kWords = kCalendarCycles / 64;
  // Forget the bookings of cycles that have passed (the events being processed are at or after
  // the last one), a word at a time.
  if (calendar_clear_ + 64 <= last_cycle_) [[unlikely]] forget_bookings();
  if (t >= calendar_clear_ + kCalendarCycles - 128) {  // beyond the window: book later
    slots_[slot].phase = Phase::kBook;
    push(slot, t);
    return;
  }
  // A free cycle in t's own word (the common case) is before t + 64, inside the window.
  uint64_t& word = step_calendar_[(t / 64) % kWords];
  const uint64_t free_bits = ~word & (~uint64_t{0} << (t % 64));
  if (!free_bits) [[unlikely]] {
    book_step_beyond(slot, t);
    return;
  }
  const uint64_t c = t / 64 * 64 + static_cast<uint64_t>(std::countr_zero(free_bits));
  word |= uint64_t{1} << (c % 64);
  slots_[slot].phase = Phase::kStep;
  push_ahead(slot, c);  // c >= t >= the event being processed
}

void TraversalUnit::book_step_beyond(uint32_t slot, uint64_t t) {
  constexpr uint64_t kWords = kCalendarCycles / 64;
  uint64_t c = t / 64 * 64 + 64;
  for (;;) {
    uint64_t& word = step_calendar_[(c / 64) % kWords];
    const uint64_t free_bits = ~word & (~uint64_t{0} << (c % 64));
    if (free_bits) {
      c = c / 64 * 64 + static_cast<uint64_t>(std::countr_zero(free_bits));
      word |= uint64_t{1} << (c % 64);
      break;
    }
    c = c / 64 * 64 + 64;
  }
  if (c >= calendar_clear_ + kCalendarCycles - 64) {  // the window is full: book later
    step_calendar_[(c / 64) % kWords] &= ~(uint64_t{1} << (c % 64));
    slots_[slot].phase = Phase::kBook;
    push(slot, c);
    return;
  }
  slots_[slot].phase = Phase::kStep;
  push(slot, c);
}

void TraversalUnit::forget_bookings() {
  constexpr uint64_t kWords = kCalendarCycles / 64;
  const uint64_t now_cycle = last_cycle_;
  if (now_cycle >= calendar_clear_ + kCalendarCycles) {  // a long idle gap: forget everything
    std::fill(step_calendar_.begin(), step_calendar_.end(), 0);
    calendar_clear_ = now_cycle / 64 * 64;
  }
  while (calendar_clear_ + 64 <= now_cycle) {
    step_calendar_[(calendar_clear_ / 64) % kWords] = 0;
    calendar_clear_ += 64;
  }
}

void TraversalUnit::data_ready(uint32_t slot, uint64_t ready) {
  Slot& s = slots_[slot];
  if (s.phase == Phase::kNodeWait) [[likely]] {
    // The node is in: the step is decided step_cycles later.
    const uint64_t decided = ready + p_.step_cycles;
    if (s.kind == StepKind::kInterior) {
      book_step(slot, decided);
    } else {
      s.phase = Phase::kLeafBody;
      push_ahead(slot, decided);
    }
    return;
  }
  switch (s.phase) {
    case Phase::kListWait:
      s.phase = Phase::kTriangles;
      push(slot, ready);
      return;
    case Phase::kTriWait:
      s.phase = Phase::kIsect;
      push(slot, ready);
      return;
    default:
      throw std::logic_error("traversal unit: data for a ray that waits for none");
  }
}

template <class Decoder>
void TraversalUnit::process(Slot& s, uint32_t index, uint64_t t) {
  if (s.phase == Phase::kStep) [[likely]] {
    if (s.next == s.end) {  // not reached: a ray's record ends with its last leaf
      finish_ray<Decoder>(index, t);
      return;
    }
    // The step's fetches: its node's, and for a leaf its list's and triangles'.
    s.fetches.clear();
    s.kind = RayStepLog::take_step(s.next, s.end, s.fetches) == RayStepLog::Kind::kLeaf
                 ? StepKind::kLeaf
                 : StepKind::kInterior;
    ++steps_;
    // The step pipeline takes one step a cycle (the calendar's bookings).
    if (t == last_step_cycle_) [[unlikely]] two_steps(t);
    last_step_cycle_ = t;
    s.phase = Phase::kNodeWait;
    issue_node(index, t);
    return;
  }
  if (s.phase == Phase::kBook) {
    schedule_step(index, t);
    return;
  }
  // The leaf's phases.
  const size_t first_triangle = first_triangle_fetch(s.fetches);
  switch (s.phase) {
    case Phase::kLeafBody:
      ++leaf_steps_;
      if (first_triangle == 2) {
        s.phase = Phase::kListWait;
        issue(index, 1, 2, t);
        return;
      }
      [[fallthrough]];
    case Phase::kTriangles:
      if (first_triangle < s.fetches.size()) {
        s.phase = Phase::kTriWait;
        issue(index, first_triangle, s.fetches.size(), t);
        return;
      }
      [[fallthrough]];  // an empty leaf
    case Phase::kIsect: {
      // Every triangle fetched goes through the intersection pipeline.
      const size_t tests = s.fetches.size() - first_triangle;
      const uint64_t end = lanes_.book(tests, t);
      isect_tests_ += tests;
      if (s.next == s.end)
        finish_ray<Decoder>(index, end);
      else
        schedule_step(index, end);
      return;
    }
    default:
      throw std::logic_error("traversal unit: event for a ray that waits for data");
  }
}

void TraversalUnit::issue_node(uint32_t slot, uint64_t t) {
  Slot& s = slots_[slot];
  const Fetch& f = s.fetches[0];
  const uint64_t line = node_line_.divisor();
  const uint64_t line_start = node_line_.div(f.addr) * line;
  if (!node_fast_ || f.stream != Stream::kNode || f.bytes == 0 ||
      f.addr + f.bytes > line_start + line) [[unlikely]] {
    issue(slot, 0, 1, t);
    return;
  }
  // What issue() does for one line read by direct call, on the unit's clock in its cycles,
  // with the slot's own payload.
  UnitPayload* p = s.node_payload;
  p->set_address(line_start);
  p->set_response_status(tlm::TLM_INCOMPLETE_RESPONSE);
  s.pending = 1;
  s.ready = t;
  s.issuing = true;
  uint64_t done = 0;
  if (node_direct_->read_line_cycle(*p, p->tag, t, &done)) completed(s, p, done);
  s.issuing = false;
  if (s.pending == 0) queue_.push_arrival<false>(s.ready, slot);  // >= t
}

void TraversalUnit::issue(uint32_t slot, size_t first, size_t last, uint64_t t) {
  Slot& s = slots_[slot];
  s.pending = 0;
  s.ready = t;
  s.issuing = true;
  const uint64_t at_ps = t * period_ps_;
  for (size_t i = first; i < last; ++i) {
    const Fetch& f = s.fetches[i];
    if (f.bytes == 0) continue;
    const bool node = f.stream == Stream::kNode;
    const FastDivider& lines = node ? node_line_ : data_line_;
    const uint64_t line = lines.divisor();
    auto& socket = node ? node_socket : data_socket;
    DirectTarget* direct = node ? node_direct_ : data_direct_;
    for (uint64_t a = f.addr; a < f.addr + f.bytes;) {
      const uint64_t line_start = lines.div(a) * line;
      const uint64_t end = std::min<uint64_t>(f.addr + f.bytes, line_start + line);
      UnitPayload* p;
      if (!free_payloads_) {
        p = &payloads_.emplace_back();
        p->tag = new FetchTag;
        p->set_extension(p->tag);
      } else {
        p = free_payloads_;
        free_payloads_ = p->next_free;
      }
      FetchTag* tag = p->tag;
      tag->stream = f.stream;
      tag->owner = slot;
      tag->reply_to = direct ? this : nullptr;  // answered as it was sent
      // One request per line touched, for the whole line: the caches fill lines, and a data
      // path straight to DRAM reads whole bursts (the functional tier's accounting).
      init_read(*p, line_start, static_cast<uint32_t>(line));
      ++s.pending;
      if (direct) {
        uint64_t done_ps = 0;
        // The node L1 called as an L1Cache: no virtual call on the hot path.
        if (node ? node_direct_->read_tagged_at(*p, tag, at_ps, &done_ps)
                 : direct->read_tagged_at(*p, tag, at_ps, &done_ps))
          completed(s, p, cycle_at_or_after(done_ps));
      } else {
        tlm::tlm_phase phase = tlm::BEGIN_REQ;
        sc_core::sc_time delay = ps(at_ps - now_ps());
        if (socket->nb_transport_fw(*p, phase, delay) == tlm::TLM_COMPLETED)
          arrived(*p, now_ps() + delay.value());
      }
      a = end;
    }
  }
  s.issuing = false;
  if (s.pending == 0) queue_.push_arrival(s.ready, slot);
}

tlm::tlm_sync_enum TraversalUnit::nb_transport_bw(tlm::tlm_generic_payload& trans,
                                                  tlm::tlm_phase& phase,
                                                  sc_core::sc_time& delay) {
  if (phase == tlm::BEGIN_RESP) arrived(trans, now_ps() + delay.value());
  return tlm::TLM_COMPLETED;
}

void TraversalUnit::two_steps(uint64_t cycle) {
  throw std::logic_error("traversal unit: two steps booked at cycle " + std::to_string(cycle));
}

void TraversalUnit::memory_error(const tlm::tlm_generic_payload& trans) {
  throw std::logic_error("traversal unit: memory error at address " +
                         std::to_string(trans.get_address()));
}

void TraversalUnit::arrived(tlm::tlm_generic_payload& trans, uint64_t at_ps) {
  check_response(trans);
  UnitPayload& p = static_cast<UnitPayload&>(trans);  // ours: sent by issue()
  const uint32_t slot = p.tag->owner;
  if (p.pooled) free_payload(&p);
  Slot& s = slots_[slot];
  s.ready = std::max(s.ready, cycle_at_or_after(at_ps));
  if (--s.pending == 0 && !s.issuing) queue_.push_arrival(s.ready, slot);
}

void TraversalUnit::answered(tlm::tlm_generic_payload& trans, uint64_t at_ps) {
  arrived(trans, at_ps);
}

void TraversalUnit::write_stats(Stats& stats) const {
  stats.set("unit.rays", rays_);
  stats.set("unit.steps", steps_);
  stats.set("unit.leaf_steps", leaf_steps_);
  stats.set("unit.isect_tests", isect_tests_);
  stats.set("unit.max_stack_depth", max_stack_);
  stats.set("unit.stack_overflow_steps", stack_overflows_);
  stats.set("unit.events", events_processed_);      // simulator effort: unit events processed
  stats.set("unit.kernel_waits", kernel_waits_);    // and SystemC waits (memory-horizon syncs)
}

}  // namespace rtusim
