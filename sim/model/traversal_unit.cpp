#include "model/traversal_unit.h"

#include <algorithm>
#include <stdexcept>

#include "layout/layout_dispatch.h"
#include "util/error.h"
#include "util/stats.h"

namespace rtusim {

void validate(const UnitParams& p) {
  auto at_least_1 = [](uint64_t v, const char* key) {
    if (v == 0) throw InputError(std::string(key) + ": must be at least 1");
  };
  at_least_1(p.rays_in_flight, "sim.rays_in_flight");
  at_least_1(p.clock_period_ps, "sim.clock_mhz");
  at_least_1(p.stack_depth, "sim.stack_depth");
  at_least_1(p.isect_lanes, "isect.lanes");
  at_least_1(p.isect_interval_cycles, "isect.interval_cycles");
  at_least_1(p.node_line_bytes, "l1.line");
  at_least_1(p.data_line_bytes, "dcache.line");
  if (p.stack_depth > TraversalState::kStackDepth)
    throw InputError("sim.stack_depth: " + std::to_string(p.stack_depth) + " is more than " +
                     std::to_string(TraversalState::kStackDepth) + " entries");
}

namespace {
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
      period_(p.clock_period_ps),
      image_(image),
      host_(host),
      slots_(p.rays_in_flight),
      lane_free_ps_(p.isect_lanes, 0) {
  node_socket.register_nb_transport_bw(this, &TraversalUnit::nb_transport_bw);
  data_socket.register_nb_transport_bw(this, &TraversalUnit::nb_transport_bw);
  SC_THREAD(run);
}

uint64_t TraversalUnit::horizon() const {
  uint64_t h = MemoryHorizon::kNever;
  for (const MemoryHorizon* m : horizons_) h = std::min(h, m->horizon_ps());
  return h;
}

void TraversalUnit::run() {
  for (;;) {
    // A batch posted before the first sc_start() notifies before this thread waits: check.
    if (!host_.has_work()) {
      wait(host_.posted());
      continue;
    }
    with_layout_decoder(image_, [&]<class Decoder>() { run_batch<Decoder>(); });
  }
}

template <class Decoder>
void TraversalUnit::run_batch() {
  const uint64_t t0 = align_up(now_ps());
  last_ps_ = t0;
  for (uint32_t i = 0; i < slots_.size(); ++i) start_ray(i, t0);
  while (active_ > 0) {
    const uint64_t h = horizon();
    if (events_.empty() || events_.top().t_ps >= h) {
      // Nothing to do before the memory acts on its own: let the kernel get there.
      if (h == MemoryHorizon::kNever)
        throw std::logic_error("traversal unit: rays wait for memory that has nothing scheduled");
      const uint64_t now = now_ps();
      wait(h > now ? ps(h - now) : sc_core::SC_ZERO_TIME);
      continue;
    }
    const Event e = events_.top();
    events_.pop();
    last_ps_ = std::max(last_ps_, e.t_ps);
    process<Decoder>(slots_[e.slot], e.slot, e.t_ps);
  }
  // The kernel catches up with the unit: the batch ends at its last event.
  const uint64_t now = now_ps();
  if (last_ps_ > now) wait(ps(last_ps_ - now));
}

void TraversalUnit::start_ray(uint32_t slot, uint64_t t) {
  Slot& s = slots_[slot];
  uint32_t index;
  while (host_.next(index)) {
    const RayRecord& r = host_.ray(index);
    traversal_begin(s.st, image_, r.ray, r.any_hit());
    ++rays_;
    if (s.st.done) {  // misses the scene's bounds: no step at all
      host_.complete(index, s.st.hit);
      continue;
    }
    s.active = true;
    s.ray = index;
    s.phase = Phase::kStep;
    ++active_;
    push(slot, t);
    return;
  }
  s.active = false;
}

void TraversalUnit::finish_ray(uint32_t slot, uint64_t t) {
  Slot& s = slots_[slot];
  host_.complete(s.ray, s.st.hit);
  s.active = false;
  --active_;
  start_ray(slot, t);
}

template <class Decoder>
void TraversalUnit::process(Slot& s, uint32_t index, uint64_t t) {
  switch (s.phase) {
    case Phase::kStep: {
      // The pipeline takes one step per cycle, first come first served: reserve a cycle.
      const uint64_t start = std::max(t, pipe_free_ps_);
      pipe_free_ps_ = start + period_;
      if (start > t) {
        s.phase = Phase::kStepGo;
        push(index, start);
        return;
      }
      [[fallthrough]];
    }
    case Phase::kStepGo: {
      s.fetches.clear();
      Recorder rec{&s.fetches};
      s.kind = traversal_step<Decoder>(s.st, image_, rec);
      if (s.kind == StepKind::kDone) {  // only after a pop found nothing: not reached normally
        finish_ray(index, t);
        return;
      }
      ++steps_;
      max_stack_ = std::max(max_stack_, s.st.sp);
      if (s.st.sp > static_cast<int>(p_.stack_depth)) ++stack_overflows_;
      s.phase = Phase::kNodeWait;
      issue(index, 0, 1, t);
      return;
    }
    case Phase::kNodeWait:
      s.phase = s.kind == StepKind::kInterior ? Phase::kStep : Phase::kLeafBody;
      push(index, t + uint64_t{p_.step_cycles} * period_);
      return;
    case Phase::kLeafBody:
      ++leaf_steps_;
      if (s.fetches.size() > 1 && s.fetches[1].stream == Stream::kList) {
        s.phase = Phase::kListWait;
        issue(index, 1, 2, t);
        return;
      }
      [[fallthrough]];
    case Phase::kListWait:
    case Phase::kTriangles: {
      const size_t first = s.fetches.size() > 1 && s.fetches[1].stream == Stream::kList ? 2 : 1;
      if (first == s.fetches.size()) {  // an empty leaf
        s.phase = Phase::kLeafDone;
        process<Decoder>(s, index, t);
        return;
      }
      s.phase = Phase::kTriWait;
      issue(index, first, s.fetches.size(), t);
      return;
    }
    case Phase::kTriWait: {
      // Every triangle fetched goes through the intersection pipeline.
      const size_t first = s.fetches.size() > 1 && s.fetches[1].stream == Stream::kList ? 2 : 1;
      uint64_t end = t;
      for (size_t i = first; i < s.fetches.size(); ++i) {
        auto lane = std::min_element(lane_free_ps_.begin(), lane_free_ps_.end());
        const uint64_t start = std::max(t, *lane);
        *lane = start + uint64_t{p_.isect_interval_cycles} * period_;
        end = std::max(end, start + uint64_t{p_.isect_latency_cycles} * period_);
        ++isect_tests_;
      }
      s.phase = Phase::kLeafDone;
      push(index, end);
      return;
    }
    case Phase::kLeafDone:
      if (s.st.done) {
        finish_ray(index, t);
      } else {
        s.phase = Phase::kStep;
        push(index, t);
      }
      return;
  }
}

void TraversalUnit::issue(uint32_t slot, size_t first, size_t last, uint64_t t) {
  Slot& s = slots_[slot];
  s.pending = 0;
  s.ready_ps = t;
  s.issuing = true;
  const sc_core::sc_time offset = ps(t - now_ps());
  for (size_t i = first; i < last; ++i) {
    const Fetch& f = s.fetches[i];
    if (f.bytes == 0) continue;
    const bool node = f.stream == Stream::kNode;
    const uint64_t line = node ? p_.node_line_bytes : p_.data_line_bytes;
    auto& socket = node ? node_socket : data_socket;
    for (uint64_t a = f.addr; a < f.addr + f.bytes;) {
      const uint64_t end = std::min<uint64_t>(f.addr + f.bytes, (a / line + 1) * line);
      tlm::tlm_generic_payload* p;
      if (free_payloads_.empty()) {
        p = &payloads_.emplace_back();
        p->set_extension(new FetchTag);
      } else {
        p = free_payloads_.back();
        free_payloads_.pop_back();
      }
      FetchTag* tag = p->get_extension<FetchTag>();
      tag->stream = f.stream;
      tag->owner = slot;
      // One request per line touched, for the whole line: the caches fill lines, and a data
      // path straight to DRAM reads whole bursts (the functional tier's accounting).
      init_read(*p, a / line * line, static_cast<uint32_t>(line));
      ++s.pending;
      tlm::tlm_phase phase = tlm::BEGIN_REQ;
      sc_core::sc_time delay = offset;
      if (socket->nb_transport_fw(*p, phase, delay) == tlm::TLM_COMPLETED)
        arrived(*p, now_ps() + delay.value());
      a = end;
    }
  }
  s.issuing = false;
  if (s.pending == 0) push(slot, align_up(s.ready_ps));
}

tlm::tlm_sync_enum TraversalUnit::nb_transport_bw(tlm::tlm_generic_payload& trans,
                                                  tlm::tlm_phase& phase,
                                                  sc_core::sc_time& delay) {
  if (phase == tlm::BEGIN_RESP) arrived(trans, now_ps() + delay.value());
  return tlm::TLM_COMPLETED;
}

void TraversalUnit::arrived(tlm::tlm_generic_payload& trans, uint64_t at_ps) {
  if (trans.get_response_status() != tlm::TLM_OK_RESPONSE)
    throw std::logic_error("traversal unit: memory error at address " +
                           std::to_string(trans.get_address()));
  const uint32_t slot = trans.get_extension<FetchTag>()->owner;
  free_payloads_.push_back(&trans);
  Slot& s = slots_[slot];
  s.ready_ps = std::max(s.ready_ps, at_ps);
  if (--s.pending == 0 && !s.issuing) push(slot, align_up(s.ready_ps));
}

void TraversalUnit::write_stats(Stats& stats) const {
  stats.set("unit.rays", rays_);
  stats.set("unit.steps", steps_);
  stats.set("unit.leaf_steps", leaf_steps_);
  stats.set("unit.isect_tests", isect_tests_);
  stats.set("unit.max_stack_depth", max_stack_);
  stats.set("unit.stack_overflow_steps", stack_overflows_);
}

}  // namespace rtusim
