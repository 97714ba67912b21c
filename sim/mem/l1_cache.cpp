#include "mem/l1_cache.h"

#include <algorithm>
#include <bit>
#include <stdexcept>
#include <type_traits>

#include "util/error.h"

namespace rtusim {

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
      period_ps_(p.clock_period_ps),
      cycles_(p.clock_period_ps),
      mshrs_(p.mshrs),
      mshr_count_(p.mshrs),
      mshr_line_(p.mshrs, 0),
      mshr_fill_(p.mshrs, 0) {
  tags_.visit([this](auto& cache) {
    tag_cache_ = &cache;
    using Cache = std::remove_reference_t<decltype(cache)>;
    read_cycle_ = [](L1Cache& l1, tlm::tlm_generic_payload& trans, const FetchTag* tag,
                     uint64_t t, uint64_t* answer_cycle) {
      return l1.read_cycle_as<Cache>(trans, tag, t, answer_cycle);
    };
    advance_ = [](L1Cache& l1) { l1.advance_as<Cache>(); };
  });
  for (size_t i = 0; i < mshrs_.size(); ++i) {
    mshrs_[i].tag = new FetchTag;
    mshrs_[i].tag->owner = static_cast<uint32_t>(i);
    mshrs_[i].payload.set_extension(mshrs_[i].tag);
  }
  target_socket.register_nb_transport_fw(this, &L1Cache::nb_transport_fw);
  initiator_socket.register_nb_transport_bw(this, &L1Cache::nb_transport_bw);
  SC_METHOD(wake);
  sensitive << wake_;
  dont_initialize();
}

// ---- Upstream: requests in, answers out -----------------------------------------------------

tlm::tlm_sync_enum L1Cache::nb_transport_fw(tlm::tlm_generic_payload& trans,
                                            tlm::tlm_phase& phase, sc_core::sc_time& delay) {
  if (phase == tlm::END_RESP) return tlm::TLM_COMPLETED;
  if (phase != tlm::BEGIN_REQ) {
    trans.set_response_status(tlm::TLM_GENERIC_ERROR_RESPONSE);
    return tlm::TLM_COMPLETED;
  }
  const uint64_t now = now_ps();
  uint64_t done = 0;
  if (!read_at(trans, now + delay.value(), &done)) {
    phase = tlm::END_REQ;
    return tlm::TLM_UPDATED;
  }
  if (trans.get_response_status() == tlm::TLM_OK_RESPONSE) {
    phase = tlm::END_REQ;
    delay = ps(done - now);
  }
  return tlm::TLM_COMPLETED;
}

bool L1Cache::read_at(tlm::tlm_generic_payload& trans, uint64_t at_ps, uint64_t* done_ps) {
  return read_tagged_at(trans, trans.get_extension<FetchTag>(), at_ps, done_ps);
}

bool L1Cache::read_tagged_at(tlm::tlm_generic_payload& trans, const FetchTag* tag,
                             uint64_t at_ps, uint64_t* done_ps) {
  uint64_t answer = 0;
  if (!valid_read(trans)) {
    *done_ps = at_ps;
    return true;
  }
  if (!read_cycle_(*this, trans, tag, cycles_.div_up(at_ps), &answer))
    return false;
  *done_ps = answer * period_ps_;
  return true;
}

template <class Cache>
bool L1Cache::read_cycle_as(tlm::tlm_generic_payload& trans, const FetchTag* tag, uint64_t t,
                            uint64_t* answer_cycle) {
  const uint64_t addr = trans.get_address();
  const uint64_t c = std::max(t, next_lookup_);
  Cache& tags = *static_cast<Cache*>(tag_cache_);
  if (!queue_empty() || !decidable_at(c * period_ps_))
    return read_general_as(tags, trans, tag, t, answer_cycle);
  // Decidable now, nothing queued: what read_general_as() does in this case (the request
  // record built only where a call takes it).
  if (c < busy_until_) {
    const Request r{&trans, tag, t};
    return settle(lookup_as(tags, r, c, answer_cycle), r, c);
  }
  // No MSHR busy: no merge, and the first MSHR is the lowest free one (what lookup() does in
  // this case).
  next_lookup_ = c + 1;
  if (tags.access(addr)) {
    ++hits_;
    *answer_cycle = c + p_.hit_cycles;
    trans.set_response_status(tlm::TLM_OK_RESPONSE);  // settle(kAnswered)
    return true;
  }
  const Request r{&trans, tag, t};
  return settle(primary_miss(r, 0, addr >> offset_bits_, c, answer_cycle), r, c);
}

template <class Cache>
bool L1Cache::read_general_as(Cache& tags, tlm::tlm_generic_payload& trans, const FetchTag* tag,
                              uint64_t t, uint64_t* answer_cycle) {
  // The downstream may have moved on (else the backlog's front is stuck as advance() left it).
  if (!queue_empty() && !(stalled_ && decidable_ps() <= stalled_limit_ps_)) advance_as<Cache>();
  const uint64_t c = std::max(t, next_lookup_);
  if (!queue_empty() || !decidable_at(c * period_ps_)) {
    // Behind a backlog the front, and so the horizon and the wake-up, stay as they are (driven
    // by call there is no wake-up to renew).
    const bool front = queue_empty();
    queue_push({&trans, tag, t});
    if (front || !driven_by_call_) schedule_wake();
    return false;
  }
  // Decidable now: a hit or a merge with a known fill completes in the return path; blocked,
  // it cannot go on before the first fill, which is after t: decided later.
  const Request r{&trans, tag, t};
  return settle(lookup_as(tags, r, c, answer_cycle), r, c);
}

void L1Cache::respond(tlm::tlm_generic_payload& trans, const FetchTag* tag, uint64_t cycle) {
  trans.set_response_status(tlm::TLM_OK_RESPONSE);
  if (tag && tag->reply_to) {
    tag->reply_to->answered(trans, cycle * period_ps_);
    return;
  }
  tlm::tlm_phase phase = tlm::BEGIN_RESP;
  sc_core::sc_time delay = ps(cycle * period_ps_ - now_ps());
  target_socket->nb_transport_bw(trans, phase, delay);
}

// ---- The lookup port --------------------------------------------------------------------------

uint64_t L1Cache::first_fill() const {
  uint64_t first = kUnknown;
  for (const uint64_t f : mshr_fill_) first = std::min(first, f);
  return first;
}

template <class Cache>
L1Cache::Outcome L1Cache::lookup_as(Cache& tags, const Request& r, uint64_t c,
                                   uint64_t* answer_cycle) {
  const uint64_t addr = r.trans->get_address();
  const uint64_t line = addr >> offset_bits_;
  // A busy MSHR for the line (a merge; the last such, should there be several) and the lowest
  // free one; none: n.
  const size_t n = mshr_count_;
  size_t match = n, free = n;
  if (c >= busy_until_) {  // none busy (the common case): the first is the lowest free one
    free = 0;
  } else if (n <= 64 && !((busy_lines_ >> (line & 63)) & 1) &&
             (busy_mask_ | (~uint64_t{0} << (n - 1) << 1)) != ~uint64_t{0}) {
    // No busy MSHR holds the line (its bit is clear) and one is surely free (not in
    // busy_mask_): no merge, never blocked. A hit is decided without the MSHRs; a miss takes the
    // lowest free one.
    next_lookup_ = c + 1;
    if (tags.access(addr)) {
      ++hits_;
      *answer_cycle = c + p_.hit_cycles;
      return Outcome::kAnswered;
    }
    const uint64_t* const fills = mshr_fill_.data();
    uint64_t idle = ~busy_mask_ & (~uint64_t{0} >> (64 - n));
    for (uint64_t left = busy_mask_; left; left &= left - 1) {
      const size_t i = static_cast<size_t>(std::countr_zero(left));
      if (c >= fills[i]) idle |= uint64_t{1} << i;
    }
    return primary_miss(r, static_cast<size_t>(std::countr_zero(idle)), line, c, answer_cycle);
  } else if (n <= 64) {
    // The MSHRs of busy_mask_ only (the others are free at c); those found free drop out. In
    // locals: a store to the mask would make the arrays' next loads wait for it.
    const uint64_t* const fills = mshr_fill_.data();
    const uint64_t* const lines = mshr_line_.data();
    uint64_t busy = busy_mask_;
    for (uint64_t left = busy; left; left &= left - 1) {
      const size_t i = static_cast<size_t>(std::countr_zero(left));
      if (c < fills[i]) {
        if (lines[i] == line) match = i;  // ascending: the last such wins
      } else {
        busy &= ~(uint64_t{1} << i);
      }
    }
    if (busy != busy_mask_) {  // some dropped out: their lines too
      busy_mask_ = busy;
      uint64_t bits = 0;
      for (uint64_t left = busy; left; left &= left - 1)
        bits |= uint64_t{1} << (lines[std::countr_zero(left)] & 63);
      busy_lines_ = bits;
    }
    const uint64_t idle = ~busy & (~uint64_t{0} >> (64 - n));
    if (idle) free = static_cast<size_t>(std::countr_zero(idle));
  } else {
    // 64 MSHRs at a time, as bit masks.
    for (size_t base = 0; base < n; base += 64) {
      const size_t k = std::min<size_t>(64, n - base);
      uint64_t busy = 0, same = 0;
      for (size_t i = 0; i < k; ++i) {
        busy |= uint64_t{c < mshr_fill_[base + i]} << i;
        same |= uint64_t{mshr_line_[base + i] == line} << i;
      }
      if (const uint64_t merge = busy & same)
        match = base + 63 - static_cast<size_t>(std::countl_zero(merge));
      const uint64_t idle = ~busy & (~uint64_t{0} >> (64 - k));
      if (free == n && idle) free = base + static_cast<size_t>(std::countr_zero(idle));
    }
  }
  if (match == n && free == n && !tags.contains(addr)) return Outcome::kBlocked;
  next_lookup_ = c + 1;
  if (match != n) {
    ++merged_;
    tags.access(addr);  // every lookup is one tag access
    if (mshr_fill_[match] != kUnknown) {
      *answer_cycle = mshr_fill_[match];
      return Outcome::kAnswered;
    }
    mshrs_[match].waiters.push_back(r);
    return Outcome::kWaiting;
  }
  if (tags.access(addr)) {
    ++hits_;
    *answer_cycle = c + p_.hit_cycles;
    return Outcome::kAnswered;
  }
  return primary_miss(r, free, line, c, answer_cycle);
}

L1Cache::Outcome L1Cache::primary_miss(const Request& r, size_t index, uint64_t line,
                                       uint64_t c, uint64_t* answer_cycle) {
  // A primary miss (the line is now allocated): the MSHR reads the line downstream at c + H.
  ++primary_;
  stalled_ = false;
  if (r.blocked_at != kUnknown) stall_cycles_ += c - r.blocked_at;
  Mshr& m = mshrs_[index];
  mshr_line_[index] = line;
  m.request_cycle = r.t;
  mshr_fill_[index] = kUnknown;
  if (index < 64) {
    if (c >= busy_until_) busy_mask_ = busy_lines_ = 0;  // none busy at c
    busy_mask_ |= uint64_t{1} << index;
    busy_lines_ |= uint64_t{1} << (line & 63);
  }
  busy_until_ = kUnknown;
  m.waiters.clear();
  const FetchTag* up = r.tag;
  m.tag->stream = up ? up->stream : Stream::kNode;
  m.tag->reply_to = downstream_direct_ ? this : nullptr;  // answered as it is sent
  init_read(m.payload, line << offset_bits_, static_cast<uint32_t>(line_bytes_));
  const uint64_t read_ps = (c + p_.hit_cycles) * period_ps_;
  bool completed;
  uint64_t done_ps = read_ps;
  if (downstream_direct_) {
    completed = downstream_direct_->read_tagged_at(m.payload, m.tag, read_ps, &done_ps);
  } else {
    tlm::tlm_phase phase = tlm::BEGIN_REQ;
    const uint64_t now = now_ps();
    sc_core::sc_time delay = ps(read_ps - now);
    completed = initiator_socket->nb_transport_fw(m.payload, phase, delay) == tlm::TLM_COMPLETED;
    done_ps = now + delay.value();
  }
  if (completed) {
    fill(index, done_ps);  // answered at once: the fill is known
    *answer_cycle = mshr_fill_[index];
    return Outcome::kAnswered;
  }
  m.waiters.push_back(r);
  return Outcome::kWaiting;
}

template <class Cache>
void L1Cache::advance_as() {
  Cache& tags = *static_cast<Cache*>(tag_cache_);
  while (!queue_empty()) {
    Request& r = queue_front();
    const uint64_t limit = decidable_ps();
    // Its lookup's cycle: refused every cycle until the first fill frees an MSHR, it is
    // decidable once no fill unknown so far can come earlier.
    const uint64_t c = r.blocked_at != kUnknown ? first_fill() : std::max(r.t, next_lookup_);
    if (c == kUnknown || c * period_ps_ > limit) {
      stall(limit);
      break;
    }
    uint64_t answer = 0;
    const Outcome o = lookup_as(tags, r, c, &answer);
    if (o == Outcome::kBlocked) {
      r.blocked_at = c;
      continue;
    }
    tlm::tlm_generic_payload* trans = r.trans;
    const FetchTag* tag = r.tag;
    queue_pop();
    if (o == Outcome::kAnswered) respond(*trans, tag, answer);
  }
  schedule_wake();
}

void L1Cache::schedule_wake() {
  update_horizon();
  if (driven_by_call_) return;
  // An earlier notification overrides a pending later one.
  const uint64_t h = horizon_ps_;
  if (h != kNever) wake_.notify(ps(h - std::min(h, now_ps())));
}

void L1Cache::update_horizon() {
  uint64_t h = kNever;
  if (!queue_empty()) {
    const Request& r = queue_front();
    if (r.blocked_at != kUnknown) {
      const uint64_t c = first_fill();  // unknown: the downstream's horizon bounds the initiator
      h = c == kUnknown ? kNever : c * period_ps_;
    } else {
      h = std::max(r.t, next_lookup_) * period_ps_;
    }
  }
  if (h == horizon_ps_) return;
  horizon_ps_ = h;
  horizon_changed();
}

void L1Cache::wake() { advance(); }

// ---- Downstream: fills ------------------------------------------------------------------------

tlm::tlm_sync_enum L1Cache::nb_transport_bw(tlm::tlm_generic_payload& trans,
                                            tlm::tlm_phase& phase, sc_core::sc_time& delay) {
  if (phase == tlm::BEGIN_RESP) answered(trans, now_ps() + delay.value());
  return tlm::TLM_COMPLETED;
}

void L1Cache::answered(tlm::tlm_generic_payload& trans, uint64_t at_ps) {
  // One of the MSHRs' payloads (their reads name the cache as reply_to): its index from its
  // address, no extension lookup (a library call).
  const size_t index = static_cast<size_t>(reinterpret_cast<const char*>(&trans) -
                                           reinterpret_cast<const char*>(&mshrs_[0].payload)) /
                       sizeof(Mshr);
  Mshr& m = mshrs_[index];
  fill(index, at_ps);
  for (const Request& w : m.waiters) respond(*w.trans, w.tag, mshr_fill_[index]);
  m.waiters.clear();
  advance();  // a blocked port may go on
}

void L1Cache::fill(size_t m, uint64_t done_ps) {
  // One fill per cycle: the first cycle at or after the completion that no known fill holds.
  // The latest fill cycle among the other MSHRs is found in the same scan.
  uint64_t c = cycles_.div_up(done_ps), latest = 0;
  const uint64_t* const fills = mshr_fill_.data();
  const size_t n = mshr_fill_.size();
  for (bool taken = true; taken;) {
    taken = false;
    latest = 0;
    for (size_t o = 0; o < n; ++o) {
      if (o == m) continue;
      if (fills[o] == c) {
        ++c;
        taken = true;
      }
      latest = std::max(latest, fills[o]);
    }
  }
  // The decidability rule (l1_cache.h) guarantees lookups never run ahead of a fill.
  if (c < next_lookup_)
    throw std::logic_error(std::string(name()) + ": a fill at cycle " + std::to_string(c) +
                           " became known after the lookup at cycle " +
                           std::to_string(next_lookup_ - 1) + " (the downstream decided late)");
  mshr_fill_[m] = c;
  stalled_ = false;
  busy_until_ = std::max(latest, c);
  ++fills_;
  miss_latency_cycles_ += c - mshrs_[m].request_cycle;
}

}  // namespace rtusim
