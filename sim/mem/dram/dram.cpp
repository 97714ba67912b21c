#include "mem/dram/dram.h"

#include "mem/dram/dram_backends.h"

#include <algorithm>
#include <stdexcept>

namespace rtusim {

Dram::Dram(const sc_core::sc_module_name& name, const DramParams& p)
    : Dram(name, make_dram_backend(p)) {}

Dram::Dram(const sc_core::sc_module_name& name, std::unique_ptr<DramBackend> backend)
    : sc_module(name), target_socket("target_socket"), backend_(std::move(backend)) {
  target_socket.register_nb_transport_fw(this, &Dram::nb_transport_fw);
  SC_METHOD(decide);
  sensitive << wake_;
  dont_initialize();
}

tlm::tlm_sync_enum Dram::nb_transport_fw(int id, tlm::tlm_generic_payload& trans,
                                         tlm::tlm_phase& phase, sc_core::sc_time& delay) {
  if (phase == tlm::END_RESP) return tlm::TLM_COMPLETED;
  if (phase != tlm::BEGIN_REQ || trans.get_command() != tlm::TLM_READ_COMMAND) {
    trans.set_response_status(tlm::TLM_COMMAND_ERROR_RESPONSE);
    return tlm::TLM_COMPLETED;
  }
  accept(trans, trans.get_extension<FetchTag>(), id, nullptr,
         now_ps() + delay.value());  // answered through the socket
  phase = tlm::END_REQ;
  return tlm::TLM_UPDATED;
}

bool Dram::read_tagged_at(tlm::tlm_generic_payload& trans, const FetchTag* tag, uint64_t at_ps,
                          uint64_t* done_ps) {
  if (trans.get_command() != tlm::TLM_READ_COMMAND) {
    trans.set_response_status(tlm::TLM_COMMAND_ERROR_RESPONSE);
    *done_ps = at_ps;
    return true;
  }
  if (!tag || !tag->reply_to)
    throw std::logic_error("DRAM read_at: the payload names no initiator to answer");
  accept(trans, tag, -1, tag->reply_to, at_ps);
  return false;
}

void Dram::accept(tlm::tlm_generic_payload& trans, const FetchTag* tag, int socket_id,
                  DirectInitiator* reply_to, uint64_t arrival_ps) {
  uint64_t rid;
  if (free_ids_.empty()) {
    rid = pending_.size();
    pending_.push_back({&trans, socket_id, reply_to});
  } else {
    rid = free_ids_.back();
    free_ids_.pop_back();
    pending_[rid] = {&trans, socket_id, reply_to};
  }
  backend_->enqueue({rid, trans.get_address(), trans.get_data_length(), arrival_ps,
                     tag ? tag->stream : Stream::kNode});
  update_horizon();
  schedule_wakeup();
}

void Dram::schedule_wakeup() {
  if (driven_by_call_) return;
  const uint64_t next = backend_->next_decision_ps();
  if (next == DramBackend::kNever) return;
  const uint64_t now = now_ps();
  if (wake_pending_ && wake_ps_ <= std::max(next, now)) return;  // already woken by then
  wake_pending_ = true;
  wake_ps_ = std::max(next, now);
  wake_.notify(ps(wake_ps_ - now));  // an earlier pending notification wins
}

void Dram::decide() {
  wake_pending_ = false;
  decide_at(now_ps());
}

void Dram::decide_at(uint64_t at_ps) {
  done_.clear();
  backend_->advance(at_ps, done_);
  // The earliest completion after each answer, so the horizon covers those not answered yet
  // (none after the last: with one decision, the common case, nothing to find).
  const size_t n = done_.size();
  if (n > 1) {
    later_done_ps_.resize(n);
    for (size_t i = n, earliest = kNever; i-- > 0;) {
      later_done_ps_[i] = earliest;
      earliest = std::min<uint64_t>(earliest, done_[i].done_ps);
    }
  }
  for (size_t i = 0; i < n; ++i) {
    const DramCompletion& c = done_[i];
    // Every completion comes after its decision time, so this is at or after at_ps.
    const uint64_t later = i + 1 == n ? kNever : later_done_ps_[i];
    unanswered_ps_ = later == kNever ? kNever : later - 1;
    update_horizon();
    const Pending p = pending_[c.id];
    free_ids_.push_back(c.id);
    p.trans->set_response_status(tlm::TLM_OK_RESPONSE);
    if (p.reply_to) {
      p.reply_to->answered(*p.trans, c.done_ps);
      continue;
    }
    tlm::tlm_phase phase = tlm::BEGIN_RESP;
    sc_core::sc_time delay = ps(c.done_ps - now_ps());
    target_socket[p.socket_id]->nb_transport_bw(*p.trans, phase, delay);  // END_RESP implied
  }
  unanswered_ps_ = kNever;
  update_horizon();
  schedule_wakeup();
}

}  // namespace rtusim
