#include "rtl_l1_adapter.h"

#include <algorithm>
#include <stdexcept>

#include "rtl/rtl_l1_registry.h"
#include "util/error.h"
#include "util/stats.h"

namespace rtusim {

namespace {
constexpr uint32_t kMaxIds = 1u << RtlL1Fixed::kIdBits;
// The registry (what config validation checks) and the Verilated builds agree.
static_assert(RtlL1Build::kMshrs == RtlL1Fixed::kMshrs);
static_assert(RtlL1Build::kHitCycles == RtlL1Fixed::kHitLatencyCycles + 1);  // + acceptance edge
}  // namespace

RtlL1Adapter::RtlL1Adapter(const sc_core::sc_module_name& name, const L1Params& p,
                           const std::string& vcd_path, bool idle_while_awaiting_fills)
    : sc_module(name),
      target_socket("target_socket"),
      initiator_socket("initiator_socket"),
      p_(p),
      period_(p.clock_period_ps),
      idle_while_awaiting_fills_(idle_while_awaiting_fills) {
  validate(p_, basename());
  rtl_l1_build(p_.cache);  // InputError for an unbuilt combination
  if (p_.mshrs != RtlL1Fixed::kMshrs || p_.hit_cycles != RtlL1Build::kHitCycles)
    throw InputError("l1.model = rtl: the RTL L1 has " + std::to_string(RtlL1Fixed::kMshrs) +
                     " MSHRs and a " + std::to_string(RtlL1Build::kHitCycles) +
                     "-cycle hit (l1.mshrs, l1.hit_cycles)");
  if (period_ < 2) throw InputError("sim.clock_mhz: too fast for the RTL L1's clock");
  rtl_ = make_rtl_l1("rtl", p_.cache, clk_, sig_);
  target_socket.register_nb_transport_fw(this, &RtlL1Adapter::nb_transport_fw);
  initiator_socket.register_nb_transport_bw(this, &RtlL1Adapter::nb_transport_bw);
  if (!vcd_path.empty()) {
    std::string stem = vcd_path;  // SystemC appends ".vcd"
    if (stem.size() > 4 && stem.ends_with(".vcd")) stem.resize(stem.size() - 4);
    vcd_ = sc_core::sc_create_vcd_trace_file(stem.c_str());
    vcd_->set_time_unit(1, sc_core::SC_PS);
    const std::string m = std::string(basename()) + ".";
    sc_core::sc_trace(vcd_, clk_, m + "clk");
    sc_core::sc_trace(vcd_, sig_.rst_n, m + "rst_n");
    sc_core::sc_trace(vcd_, sig_.i_req_valid, m + "i_req_valid");
    sc_core::sc_trace(vcd_, sig_.o_req_ready, m + "o_req_ready");
    sc_core::sc_trace(vcd_, sig_.i_req_addr, m + "i_req_addr");
    sc_core::sc_trace(vcd_, sig_.i_req_id, m + "i_req_id");
    sc_core::sc_trace(vcd_, sig_.o_resp_valid, m + "o_resp_valid");
    sc_core::sc_trace(vcd_, sig_.i_resp_ready, m + "i_resp_ready");
    sc_core::sc_trace(vcd_, sig_.o_resp_id, m + "o_resp_id");
    sc_core::sc_trace(vcd_, sig_.o_resp_hit, m + "o_resp_hit");
    sc_core::sc_trace(vcd_, sig_.o_resp_merged, m + "o_resp_merged");
    sc_core::sc_trace(vcd_, sig_.o_mem_req_valid, m + "o_mem_req_valid");
    sc_core::sc_trace(vcd_, sig_.i_mem_req_ready, m + "i_mem_req_ready");
    sc_core::sc_trace(vcd_, sig_.o_mem_req_addr, m + "o_mem_req_addr");
    sc_core::sc_trace(vcd_, sig_.i_mem_resp_valid, m + "i_mem_resp_valid");
    sc_core::sc_trace(vcd_, sig_.i_mem_resp_addr, m + "i_mem_resp_addr");
    sc_core::sc_trace(vcd_, sig_.o_mshrs_busy, m + "o_mshrs_busy");
  }
  SC_THREAD(run);
}

RtlL1Adapter::~RtlL1Adapter() {
  if (vcd_) sc_core::sc_close_vcd_trace_file(vcd_);
}

uint64_t RtlL1Adapter::horizon_ps() const {
  if (running_) return next_edge_ps_;
  const uint64_t w = next_work_ps();
  if (w == kNever) return kNever;
  return align_up(std::max(w, now_ps())) + period_;  // its first cycle ends there
}

uint64_t RtlL1Adapter::next_work_ps() const {
  uint64_t w = kNever;
  if (offering_) w = 0;
  if (!queue_.empty()) w = std::min(w, queue_.front().t_ps);
  if (!fills_.empty()) w = std::min(w, fills_.front().drive_ps);
  return w;
}

tlm::tlm_sync_enum RtlL1Adapter::nb_transport_fw(tlm::tlm_generic_payload& trans,
                                                 tlm::tlm_phase& phase,
                                                 sc_core::sc_time& delay) {
  if (phase == tlm::END_RESP) return tlm::TLM_COMPLETED;
  const uint64_t addr = trans.get_address();
  const uint32_t len = trans.get_data_length();
  const uint64_t line = p_.cache.line_bytes;
  if (phase != tlm::BEGIN_REQ || trans.get_command() != tlm::TLM_READ_COMMAND || len == 0 ||
      addr / line != (addr + len - 1) / line) {
    trans.set_response_status(tlm::TLM_GENERIC_ERROR_RESPONSE);  // one line per request
    return tlm::TLM_COMPLETED;
  }
  if (free_ids_.empty()) {
    if (by_id_.size() >= kMaxIds)
      throw std::logic_error("rtl l1: more than 2^16 requests outstanding");
    free_ids_.push_back(static_cast<uint32_t>(by_id_.size()));
    by_id_.push_back(nullptr);
    t_by_id_.push_back(0);
  }
  const uint32_t id = free_ids_.back();
  free_ids_.pop_back();
  const uint64_t now = now_ps();
  const Request r{align_up(now + delay.value()), id};
  by_id_[id] = &trans;
  t_by_id_[id] = r.t_ps;
  ++outstanding_;
  if (cycle_open_ && !offering_ && queue_.empty() && r.t_ps <= now) {
    offer(r);  // joins the cycle being driven
  } else {
    // In time order (the unit issues in time order but a step may book ahead).
    auto it = queue_.end();
    while (it != queue_.begin() && std::prev(it)->t_ps > r.t_ps) --it;
    queue_.insert(it, r);
    if (!running_) work_.notify(sc_core::SC_ZERO_TIME);
  }
  phase = tlm::END_REQ;
  return tlm::TLM_UPDATED;
}

tlm::tlm_sync_enum RtlL1Adapter::nb_transport_bw(tlm::tlm_generic_payload& trans,
                                                 tlm::tlm_phase& phase,
                                                 sc_core::sc_time& delay) {
  if (phase == tlm::BEGIN_RESP) {
    const uint64_t done = align_up(now_ps() + delay.value());
    const Fill f{done - period_, trans.get_address()};  // driven in the cycle ending at `done`
    free_mem_payloads_.push_back(&trans);
    if (cycle_open_ && !filling_ && fills_.empty() && f.drive_ps + period_ <= next_edge_ps_) {
      drive_fill(f);  // joins the cycle being driven
      return tlm::TLM_COMPLETED;
    }
    auto it = fills_.end();
    while (it != fills_.begin() && std::prev(it)->drive_ps > f.drive_ps) --it;
    fills_.insert(it, f);
    if (!running_) work_.notify(sc_core::SC_ZERO_TIME);
  }
  return tlm::TLM_COMPLETED;
}

void RtlL1Adapter::reset() {
  // Two edges with rst_n low, then released; all in delta cycles at time 0.
  sig_.rst_n.write(false);
  sig_.i_resp_ready.write(true);
  sig_.i_mem_req_ready.write(true);
  for (int i = 0; i < 3; ++i) {
    if (i == 2) sig_.rst_n.write(true);
    clk_.write(true);
    wait(sc_core::SC_ZERO_TIME);
    wait(sc_core::SC_ZERO_TIME);
    clk_.write(false);
    wait(sc_core::SC_ZERO_TIME);
    wait(sc_core::SC_ZERO_TIME);
  }
}

void RtlL1Adapter::offer(const Request& r) {
  offering_ = true;
  offered_ = r;
  sig_.i_req_valid.write(true);
  sig_.i_req_addr.write(by_id_[r.id]->get_address());
  sig_.i_req_id.write(r.id);
}

void RtlL1Adapter::drive_fill(const Fill& f) {
  filling_ = true;
  sig_.i_mem_resp_valid.write(true);
  sig_.i_mem_resp_addr.write(f.addr);
  --awaiting_fill_;
}

void RtlL1Adapter::drive_cycle(uint64_t start_ps) {
  filling_ = false;
  if (!fills_.empty() && fills_.front().drive_ps <= start_ps) {
    drive_fill(fills_.front());
    fills_.pop_front();
  } else {
    sig_.i_mem_resp_valid.write(false);
  }
  if (!offering_ && !queue_.empty() && queue_.front().t_ps <= start_ps) {
    offer(queue_.front());
    queue_.pop_front();
  } else if (!offering_) {
    sig_.i_req_valid.write(false);
  }
  cycle_open_ = true;
}

void RtlL1Adapter::sample(uint64_t edge_ps) {
  cycle_open_ = false;
  ++clocked_cycles_;
  if (offering_) {
    if (sig_.o_req_ready.read()) {
      offering_ = false;
    } else if (sig_.o_mshrs_busy.read() == RtlL1Fixed::kMshrs) {
      ++stall_cycles_;
    }
  }
  if (sig_.o_resp_valid.read()) {
    const uint32_t id = sig_.o_resp_id.read();
    tlm::tlm_generic_payload* trans = by_id_.at(id);
    if (!trans) throw std::logic_error("rtl l1: response for an idle id");
    if (sig_.o_resp_hit.read()) {
      ++hits_;
    } else if (sig_.o_resp_merged.read()) {
      ++merged_;
    } else {
      ++primary_;
      miss_latency_cycles_ += (edge_ps - t_by_id_[id]) / period_;
    }
    by_id_[id] = nullptr;
    free_ids_.push_back(id);
    --outstanding_;
    trans->set_response_status(tlm::TLM_OK_RESPONSE);
    tlm::tlm_phase phase = tlm::BEGIN_RESP;
    sc_core::sc_time delay = sc_core::SC_ZERO_TIME;
    target_socket->nb_transport_bw(*trans, phase, delay);
  }
  if (sig_.o_mem_req_valid.read()) {
    tlm::tlm_generic_payload* m;
    if (free_mem_payloads_.empty()) {
      m = &mem_payloads_.emplace_back();
      m->set_extension(new FetchTag);  // stream kNode
    } else {
      m = free_mem_payloads_.back();
      free_mem_payloads_.pop_back();
    }
    init_read(*m, sig_.o_mem_req_addr.read(), p_.cache.line_bytes);
    ++awaiting_fill_;
    tlm::tlm_phase phase = tlm::BEGIN_REQ;
    sc_core::sc_time delay = sc_core::SC_ZERO_TIME;
    if (initiator_socket->nb_transport_fw(*m, phase, delay) == tlm::TLM_COMPLETED) {
      phase = tlm::BEGIN_RESP;
      nb_transport_bw(*m, phase, delay);
    }
  }
}

bool RtlL1Adapter::quiescent() const {
  // Called with the outputs settled after an edge: nothing to drive in the next cycle and no
  // output or internal activity (an MSHR draining shows as more busy MSHRs than awaited fills).
  const uint64_t next = now_ps();
  if (offering_) return false;
  if (!queue_.empty() && queue_.front().t_ps <= next) return false;
  if (!fills_.empty() && fills_.front().drive_ps <= next) return false;
  if (!idle_while_awaiting_fills_ && (outstanding_ > 0 || awaiting_fill_ > 0)) return false;
  return !sig_.o_resp_valid.read() && !sig_.o_mem_req_valid.read() &&
         sig_.o_mshrs_busy.read() == awaiting_fill_;
}

void RtlL1Adapter::run() {
  reset();
  for (;;) {
    // Idle: the clock stands still until the next queued request or fill.
    running_ = false;
    for (;;) {
      const uint64_t now = now_ps();
      const uint64_t w = next_work_ps();
      if (w == kNever) {
        wait(work_);
        continue;
      }
      const uint64_t start = align_up(std::max(w, now));
      if (start == now) break;
      wait(sc_core::sc_time::from_value(start - now), work_);
    }
    running_ = true;
    // Clocking: one cycle per pass, starting at an edge with the outputs settled.
    for (;;) {
      const uint64_t start = now_ps();
      next_edge_ps_ = start + period_;
      drive_cycle(start);
      if (vcd_) {  // a clock that looks like one: falling mid-cycle
        wait(ps(period_ / 2));
        clk_.write(false);
        wait(ps(period_ - period_ / 2));
      } else {
        wait(ps(period_));
      }
      sample(next_edge_ps_);
      clk_.write(true);
      wait(sc_core::SC_ZERO_TIME);  // the RTL evaluates the edge
      if (!vcd_) clk_.write(false);  // falls a delta later: one timed wait per cycle, not two
      wait(sc_core::SC_ZERO_TIME);  // its post-edge outputs are visible
      if (quiescent()) break;
    }
  }
}

// Registration with the core's node L1 seam (mem/node_l1.h). The anchor symbol is named in
// rtusim_rtl_l1's link options (--undefined), so this object file, and with it the registrar,
// is in every binary that links the library.
std::unique_ptr<NodeL1> make_rtl_adapter(const char* name, const L1Params& p,
                                         const std::string& vcd_path) {
  return std::make_unique<RtlL1Adapter>(name, p, vcd_path);
}

namespace {
const bool registered = (register_rtl_node_l1(&make_rtl_adapter), true);
}  // namespace

}  // namespace rtusim

extern "C" const bool* rtusim_rtl_node_l1_anchor() { return &rtusim::registered; }
