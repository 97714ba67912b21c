#include "rtl_l1_adapter.h"

#include <algorithm>
#include <exception>
#include <filesystem>
#include <stdexcept>

#include "rtl/rtl_l1_registry.h"
#include "util/error.h"

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
  if (!vcd_path.empty()) open_vcd(vcd_path);
  SC_THREAD(run);
}

void RtlL1Adapter::open_vcd(const std::string& path) {
  vcd_file_.emplace(path);  // InputError when its directory does not exist
  vcd_ = sc_core::sc_create_vcd_trace_file(vcd_file_->temp_path().c_str());
  vcd_->set_time_unit(1, sc_core::SC_PS);
  const std::string m = std::string(basename()) + ".";
  sc_core::sc_trace(vcd_, clk_, m + "clk");
  sc_core::sc_trace(vcd_, sig_.rst_n, m + "rst_n");
  sc_core::sc_trace(vcd_, sig_.i_req_valid, m + "i_req_valid");
  sc_core::sc_trace(vcd_, sig_.o_req_ready, m + "o_req_ready");
  sc_core::sc_trace(vcd_, sig_.i_req_addr, m + "i_req_addr");
  sc_core::sc_trace(vcd_, sig_.i_req_id, m + "i_req_id");
  sc_core::sc_trace(vcd_, sig_.o_req_hit, m + "o_req_hit");
  sc_core::sc_trace(vcd_, sig_.o_req_merged, m + "o_req_merged");
  sc_core::sc_trace(vcd_, sig_.o_req_mshr, m + "o_req_mshr");
  sc_core::sc_trace(vcd_, sig_.o_resp_valid, m + "o_resp_valid");
  sc_core::sc_trace(vcd_, sig_.i_resp_ready, m + "i_resp_ready");
  sc_core::sc_trace(vcd_, sig_.o_resp_id, m + "o_resp_id");
  sc_core::sc_trace(vcd_, sig_.o_mem_req_valid, m + "o_mem_req_valid");
  sc_core::sc_trace(vcd_, sig_.i_mem_req_ready, m + "i_mem_req_ready");
  sc_core::sc_trace(vcd_, sig_.o_mem_req_addr, m + "o_mem_req_addr");
  sc_core::sc_trace(vcd_, sig_.i_mem_resp_valid, m + "i_mem_resp_valid");
  sc_core::sc_trace(vcd_, sig_.i_mem_resp_addr, m + "i_mem_resp_addr");
  sc_core::sc_trace(vcd_, sig_.o_fill_valid, m + "o_fill_valid");
  sc_core::sc_trace(vcd_, sig_.o_fill_mshr, m + "o_fill_mshr");
  sc_core::sc_trace(vcd_, sig_.o_mshrs_busy, m + "o_mshrs_busy");
}

void RtlL1Adapter::finish() {
  if (!vcd_) return;
  // SystemC wrote TEMP.vcd: renamed to TEMP, then committed to the asked-for path.
  sc_core::sc_close_vcd_trace_file(vcd_);
  vcd_ = nullptr;
  std::filesystem::path written = vcd_file_->temp_path();
  written += ".vcd";
  std::filesystem::rename(written, vcd_file_->temp_path());
  vcd_file_->commit();
}

RtlL1Adapter::~RtlL1Adapter() {
  if (!vcd_) return;  // none, or committed
  sc_core::sc_close_vcd_trace_file(vcd_);
  std::filesystem::path written = vcd_file_->temp_path();
  written += ".vcd";
  std::error_code ec;
  std::filesystem::remove(written, ec);  // the run failed: no partial output
}

// ---- Upstream: requests in, answers out ---------------------------------------------------

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
    if (requests_.size() >= kMaxIds)
      throw std::logic_error("rtl l1: more than 2^16 requests outstanding");
    free_ids_.push_back(static_cast<uint32_t>(requests_.size()));
    requests_.emplace_back();
  }
  const uint32_t id = free_ids_.back();
  free_ids_.pop_back();
  requests_[id] = {&trans, cycle_at_or_after(now_ps() + delay.value())};
  ++outstanding_;
  phase = tlm::END_REQ;
  if (!offering_ && queue_.empty()) {
    queue_.push_back(id);
    const uint64_t c = head_lookup_cycle();
    if (c < first_drivable_cycle())
      throw std::logic_error("rtl l1: a request for cycle " + std::to_string(c) +
                             " arrived after that cycle began");
    if (cycle_open_ && c == cycle_) {  // joins the cycle being driven
      queue_.pop_front();
      offer(id, c);
      return tlm::TLM_UPDATED;
    }
  } else {
    queue_.push_back(id);
  }
  if (!running_) work_.notify(sc_core::SC_ZERO_TIME);
  return tlm::TLM_UPDATED;
}

void RtlL1Adapter::answer(uint32_t id, uint64_t edge_ps) {
  tlm::tlm_generic_payload* trans = requests_.at(id).trans;
  if (!trans) throw std::logic_error("rtl l1: an answer for an idle id");
  requests_[id].trans = nullptr;
  free_ids_.push_back(id);
  --outstanding_;
  trans->set_response_status(tlm::TLM_OK_RESPONSE);
  tlm::tlm_phase phase = tlm::BEGIN_RESP;
  sc_core::sc_time delay = ps(edge_ps - now_ps());
  target_socket->nb_transport_bw(*trans, phase, delay);
}

uint64_t RtlL1Adapter::head_lookup_cycle() const {
  const uint64_t t = requests_[queue_.front()].t;
  return last_lookup_ == kNone ? t : std::max(t, last_lookup_ + 1);
}

uint64_t RtlL1Adapter::first_drivable_cycle() const {
  // Not open, the cycle under way has not been driven: the clock runs from an edge (now, when
  // clocking) or stands still since one (idle), and the RTL samples its inputs only at the edge
  // that ends the cycle, so they may still be set mid-cycle.
  return cycle_open_ ? cycle_ : now_ps() / period_;
}

// ---- Downstream: line reads out, fills in -------------------------------------------------

void RtlL1Adapter::send_line_read(uint64_t addr, sc_core::sc_time delay) {
  tlm::tlm_generic_payload* m;
  if (free_mem_payloads_.empty()) {
    m = &mem_payloads_.emplace_back();
    m->set_extension(new FetchTag);  // stream kNode
  } else {
    m = free_mem_payloads_.back();
    free_mem_payloads_.pop_back();
  }
  init_read(*m, addr, p_.cache.line_bytes);
  tlm::tlm_phase phase = tlm::BEGIN_REQ;
  if (initiator_socket->nb_transport_fw(*m, phase, delay) == tlm::TLM_COMPLETED) {
    phase = tlm::BEGIN_RESP;
    nb_transport_bw(*m, phase, delay);
  }
}

tlm::tlm_sync_enum RtlL1Adapter::nb_transport_bw(tlm::tlm_generic_payload& trans,
                                                 tlm::tlm_phase& phase,
                                                 sc_core::sc_time& delay) {
  if (phase != tlm::BEGIN_RESP) return tlm::TLM_COMPLETED;
  // The fill cycle: the first at or after the completion that no other fill holds.
  uint64_t fill_cycle = cycle_at_or_after(now_ps() + delay.value());
  while (fills_.count(fill_cycle)) ++fill_cycle;
  if (fill_cycle == 0 || fill_cycle - 1 < first_drivable_cycle())
    throw std::logic_error("rtl l1: DRAM's answer for fill cycle " + std::to_string(fill_cycle) +
                           " came too late to drive the cycle before it");
  const uint64_t addr = trans.get_address();
  fills_.emplace(fill_cycle, addr);
  free_mem_payloads_.push_back(&trans);
  if (cycle_open_ && fill_cycle - 1 == cycle_) {  // joins the cycle being driven
    drive_fill(addr);
    answer_at_edge_ = true;
  } else if (!running_) {
    work_.notify(sc_core::SC_ZERO_TIME);
  }
  return tlm::TLM_COMPLETED;
}

// ---- The clocked side ---------------------------------------------------------------------

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

void RtlL1Adapter::offer(uint32_t id, uint64_t c) {
  offering_ = true;
  offered_ = id;
  offered_since_ = c;
  sig_.i_req_valid.write(true);
  sig_.i_req_addr.write(requests_[id].trans->get_address());
  sig_.i_req_id.write(id);
}

void RtlL1Adapter::drive_fill(uint64_t addr) {
  filling_ = true;
  sig_.i_mem_resp_valid.write(true);
  sig_.i_mem_resp_addr.write(addr);
}

void RtlL1Adapter::drive_cycle(uint64_t c) {
  cycle_ = c;
  filling_ = false;
  if (!fills_.empty() && fills_.begin()->first <= c)
    throw std::logic_error("rtl l1: fill cycle " + std::to_string(fills_.begin()->first) +
                           " was not driven");
  if (!fills_.empty() && fills_.begin()->first == c + 1)
    drive_fill(fills_.begin()->second);
  else
    sig_.i_mem_resp_valid.write(false);
  if (!offering_ && !queue_.empty()) {
    const uint64_t lookup = head_lookup_cycle();
    if (lookup < c)
      throw std::logic_error("rtl l1: the lookup of cycle " + std::to_string(lookup) +
                             " was not driven");
    if (lookup == c) {
      offer(queue_.front(), c);
      queue_.pop_front();
    }
  }
  if (!offering_) sig_.i_req_valid.write(false);
  // A line read on the outputs is taken at this cycle's edge (memory is always ready): it goes
  // to DRAM now, with that edge as its time, so DRAM has it before it decides at that edge.
  if (sig_.o_mem_req_valid.read())
    send_line_read(sig_.o_mem_req_addr.read(), ps((c + 1) * period_ - now_ps()));
  answer_at_edge_ = filling_ || sig_.o_resp_valid.read();
  cycle_open_ = true;
}

void RtlL1Adapter::sample(uint64_t edge_ps) {
  cycle_open_ = false;
  ++clocked_cycles_;
  // The lookup accepted at this edge: its outcome, and a miss joins its MSHR's waiters.
  if (offering_ && sig_.o_req_ready.read()) {
    offering_ = false;
    last_lookup_ = cycle_;
    stall_cycles_ += cycle_ - offered_since_;
    if (sig_.o_req_hit.read()) {
      ++hits_;
    } else {
      const uint32_t m = sig_.o_req_mshr.read();
      if (sig_.o_req_merged.read()) {
        ++merged_;
      } else {
        ++primary_;
        if (!waiters_.at(m).empty())
          throw std::logic_error("rtl l1: a primary miss in an MSHR with waiters");
        primary_t_[m] = requests_[offered_].t;
      }
      waiters_[m].push_back(offered_);
    }
  }
  // The fill of this edge: its MSHR's waiters, then a hit.
  if (filling_) {
    if (!sig_.o_fill_valid.read())
      throw std::logic_error("rtl l1: a fill matched no waiting MSHR");
    const uint32_t m = sig_.o_fill_mshr.read();
    miss_latency_cycles_ += cycle_ + 1 - primary_t_.at(m);
    ++fills_done_;
    for (const uint32_t id : waiters_[m]) answer(id, edge_ps);
    waiters_[m].clear();
    fills_.erase(fills_.begin());
  }
  if (sig_.o_resp_valid.read()) answer(sig_.o_resp_id.read(), edge_ps);
}

bool RtlL1Adapter::quiescent() const {
  // Called with the outputs settled after an edge, before the next cycle is driven: can that
  // cycle and every one up to the next queued work change nothing?
  const uint64_t next = now_ps() / period_;
  if (!idle_while_awaiting_fills_ && outstanding_ > 0) return false;
  if (sig_.o_resp_valid.read() || sig_.o_mem_req_valid.read()) return false;
  if (!fills_.empty() && fills_.begin()->first == next + 1) return false;
  if (offering_) return !sig_.o_req_ready.read();  // refused until a fill frees an MSHR
  return queue_.empty() || head_lookup_cycle() > next;
}

uint64_t RtlL1Adapter::next_work_cycle() const {
  const uint64_t now_cycle = first_drivable_cycle();
  uint64_t c = kNone;
  if (!offering_ && !queue_.empty()) c = std::max(head_lookup_cycle(), now_cycle);
  if (!fills_.empty()) c = std::min(c, std::max(fills_.begin()->first - 1, now_cycle));
  return c;
}

uint64_t RtlL1Adapter::horizon_ps() const {
  if (running_) {
    if (!cycle_open_) return now_ps();  // between an edge and the next cycle's inputs
    const uint64_t edge = (cycle_ + 1) * period_;
    return answer_at_edge_ ? edge : edge + period_;
  }
  // Idle: the first fill answers its waiters at its edge; the head, looked up in cycle c,
  // answers no earlier than c + 2 (a hit; a merge is answered at a fill, known or bounded by
  // the DRAM's own horizon).
  uint64_t h = kNever;
  if (!fills_.empty()) h = fills_.begin()->first * period_;
  if (!offering_ && !queue_.empty())
    h = std::min(h, (std::max(head_lookup_cycle(), cycle_at_or_after(now_ps())) + 2) * period_);
  return h;
}

void RtlL1Adapter::run() {
  reset();
  for (;;) {
    // Idle: the clock stands still until the next queued request or fill.
    running_ = false;
    for (;;) {
      const uint64_t c = next_work_cycle();
      if (c == kNone) {
        wait(work_);
        continue;
      }
      const uint64_t now = now_ps(), start = c * period_;
      if (start <= now) break;  // before: the cycle under way, which nothing has driven
      wait(ps(start - now), work_);
    }
    running_ = true;
    // Clocking: one cycle per pass with the outputs settled, from an edge or, when DRAM has
    // just told a fill for the next edge, from the middle of the cycle under way.
    for (uint64_t c = now_ps() / period_;; ++c) {
      drive_cycle(c);
      const uint64_t edge_ps = (c + 1) * period_;
      if (vcd_) {  // a clock that looks like one: falling mid-cycle
        const uint64_t fall_ps = c * period_ + period_ / 2;
        if (fall_ps > now_ps()) wait(ps(fall_ps - now_ps()));
        clk_.write(false);
      }
      wait(ps(edge_ps - now_ps()));
      sample(edge_ps);
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
