#include "mem/l1_cache.h"

#include <algorithm>
#include <bit>
#include <stdexcept>

#include "util/error.h"
#include "util/stats.h"

namespace rtusim {

void validate(const L1Params& p, const std::string& prefix) {
  validate(p.cache, prefix);
  if (p.hit_cycles == 0) throw InputError(prefix + ".hit_cycles: must be at least 1");
  if (p.mshrs == 0) throw InputError(prefix + ".mshrs: must be at least 1");
  if (p.clock_period_ps == 0) throw InputError("sim.clock_mhz: must be positive");
}

namespace {
const L1Params& checked(const L1Params& p, const char* name) {
  validate(p, name);
  return p;
}
}  // namespace

L1Cache::L1Cache(const sc_core::sc_module_name& name, const L1Params& p)
    : sc_module(name),
      target_socket("target_socket"),
      initiator_socket("initiator_socket"),
      p_(checked(p, basename())),
      tags_(p.cache),
      offset_bits_(static_cast<uint32_t>(std::countr_zero(p.cache.line_bytes))),
      line_bytes_(p.cache.line_bytes),
      hit_ps_(uint64_t{p.hit_cycles} * p.clock_period_ps),
      hit_time_(ps(hit_ps_)) {
  target_socket.register_nb_transport_fw(this, &L1Cache::nb_transport_fw);
  initiator_socket.register_nb_transport_bw(this, &L1Cache::nb_transport_bw);
}

tlm::tlm_sync_enum L1Cache::nb_transport_fw(tlm::tlm_generic_payload& trans,
                                            tlm::tlm_phase& phase, sc_core::sc_time& delay) {
  if (phase == tlm::END_RESP) return tlm::TLM_COMPLETED;
  const uint64_t addr = trans.get_address();
  const uint32_t len = trans.get_data_length();
  if (phase != tlm::BEGIN_REQ || trans.get_command() != tlm::TLM_READ_COMMAND || len == 0 ||
      (addr >> offset_bits_) != ((addr + len - 1) >> offset_bits_)) {
    trans.set_response_status(tlm::TLM_GENERIC_ERROR_RESPONSE);  // one line per request
    return tlm::TLM_COMPLETED;
  }
  const uint64_t now = now_ps();
  const uint64_t t = now + delay.value();
  const Result r = access(trans, t, t, false);
  if (r.kind == Result::kDone) {
    trans.set_response_status(tlm::TLM_OK_RESPONSE);
    if (r.at_ps == t + hit_ps_)
      delay += hit_time_;  // a hit: no conversion
    else
      delay = ps(r.at_ps - now);
    return tlm::TLM_COMPLETED;
  }
  phase = tlm::END_REQ;
  return tlm::TLM_UPDATED;
}

uint64_t L1Cache::free_mshr_time(uint64_t t) const {
  // Candidates: t itself and every known fill after it; the first with a busy count below the
  // MSHR count.
  auto free_at = [&](uint64_t x) {
    uint32_t busy = 0;
    for (const Mshr& m : mshrs_) busy += m.busy_at(x) ? 1 : 0;
    return busy < p_.mshrs;
  };
  if (free_at(t)) return t;
  uint64_t best = kUnknown;
  for (const Mshr& m : mshrs_)
    if (m.in_use && m.fill_ps != kUnknown && m.fill_ps > t && m.fill_ps < best && free_at(m.fill_ps))
      best = m.fill_ps;
  return best;
}

L1Cache::Result L1Cache::access(tlm::tlm_generic_payload& trans, uint64_t t,
                                uint64_t request_ps, bool retry) {
  const uint64_t now = now_ps();
  const uint64_t addr = trans.get_address();
  const uint64_t line = addr >> offset_bits_;
  // One pass: a busy MSHR for the line (a merge), and how many are busy at t.
  // Branch-free: which entry is busy is unpredictable.
  uint32_t busy = 0;
  size_t match = mshrs_.size();
  for (size_t i = 0; i < mshrs_.size(); ++i) {
    const bool b = mshrs_[i].busy_at(t);
    busy += b;
    match = b & (mshrs_[i].line == line) ? i : match;
  }
  if (match != mshrs_.size()) {
    Mshr& m = mshrs_[match];
    ++merged_;
    tags_.access(addr);  // the replacement state sees every access
    if (m.fill_ps != kUnknown) return {Result::kDone, m.fill_ps};
    m.port->waiters.push_back(&trans);
    return {Result::kPending, 0};
  }
  uint64_t free_ps = t;
  if (busy < p_.mshrs && (retry || stalled_.empty())) {
    // No stall possible: one tag access decides hit or primary miss.
    if (tags_.access(addr)) {
      ++hits_;
      return {Result::kDone, t + hit_ps_};
    }
  } else {
    if (tags_.contains(addr)) {
      tags_.access(addr);
      ++hits_;
      return {Result::kDone, t + hit_ps_};
    }
    // A primary miss: wait for an MSHR (behind any request already waiting).
    if (!retry && !stalled_.empty()) {
      stalled_.push_back({&trans, t});
      return {Result::kStalled, 0};
    }
    free_ps = free_mshr_time(t);
    if (free_ps == kUnknown) {
      stalled_.push_back({&trans, t});
      return {Result::kStalled, 0};
    }
    tags_.access(addr);  // fills the line
  }
  stall_cycles_ += (free_ps - t) / p_.clock_period_ps;
  t = free_ps;
  ++primary_;
  Mshr* m = nullptr;
  for (Mshr& cand : mshrs_)
    if (!cand.in_use || (cand.fill_ps != kUnknown && cand.fill_ps <= now)) {  // free for good
      m = &cand;
      break;
    }
  if (!m) {
    m = &mshrs_.emplace_back();
    m->port = std::make_unique<MshrPort>();
    m->port->tag = new FetchTag;
    m->port->tag->owner = static_cast<uint32_t>(mshrs_.size() - 1);
    m->port->payload.set_extension(m->port->tag);
  }
  m->in_use = true;
  m->line = line;
  m->request_ps = request_ps;
  m->alloc_ps = t;
  m->fill_ps = kUnknown;
  m->port->waiters.clear();
  const FetchTag* up = trans.get_extension<FetchTag>();
  m->port->tag->stream = up ? up->stream : Stream::kNode;
  init_read(m->port->payload, line << offset_bits_, static_cast<uint32_t>(line_bytes_));
  tlm::tlm_phase phase = tlm::BEGIN_REQ;
  sc_core::sc_time delay = ps(t + hit_ps_ - now);
  if (initiator_socket->nb_transport_fw(m->port->payload, phase, delay) == tlm::TLM_COMPLETED) {
    set_fill(*m, now + delay.value());  // answered at once: the data time is known
    return {Result::kDone, m->fill_ps};
  }
  m->port->waiters.push_back(&trans);
  return {Result::kPending, 0};
}

tlm::tlm_sync_enum L1Cache::nb_transport_bw(tlm::tlm_generic_payload& trans,
                                            tlm::tlm_phase& phase, sc_core::sc_time& delay) {
  if (phase == tlm::BEGIN_RESP) {
    Mshr& m = mshrs_[trans.get_extension<FetchTag>()->owner];
    set_fill(m, now_ps() + delay.value());
    for (tlm::tlm_generic_payload* w : m.port->waiters) respond(*w, m.fill_ps);
    m.port->waiters.clear();
    retry_stalled();
  }
  return tlm::TLM_COMPLETED;
}

void L1Cache::set_fill(Mshr& m, uint64_t done_ps) {
  m.fill_ps = align_up(done_ps);
  ++fills_;
  miss_latency_cycles_ += (m.fill_ps - m.request_ps) / p_.clock_period_ps;
}

void L1Cache::retry_stalled() {
  // A fill time became known: stalled requests, oldest first, go on when an MSHR frees for them.
  while (!stalled_.empty()) {
    const Waiter s = stalled_.front();
    // Not before now: an MSHR free earlier would have been handed over when its fill was known
    // (and entries filled before now may have been reused).
    const uint64_t t = free_mshr_time(std::max(s.t_ps, now_ps()));
    if (t == kUnknown) return;
    stalled_.pop_front();
    stall_cycles_ += (t - s.t_ps) / p_.clock_period_ps;
    const Result r = access(*s.trans, t, s.t_ps, true);  // a merge, a hit or a miss at t
    if (r.kind == Result::kDone) respond(*s.trans, r.at_ps);
  }
}

void L1Cache::respond(tlm::tlm_generic_payload& trans, uint64_t at_ps) {
  trans.set_response_status(tlm::TLM_OK_RESPONSE);
  tlm::tlm_phase phase = tlm::BEGIN_RESP;
  sc_core::sc_time delay = ps(at_ps - now_ps());
  target_socket->nb_transport_bw(trans, phase, delay);
}

}  // namespace rtusim
