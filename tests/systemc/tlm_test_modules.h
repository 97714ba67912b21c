// Test modules around the cycle tier's TLM-2.0 AT components: an initiator that sends reads at
// given times and records when each one's data is there, and memories with a fixed latency.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include <systemc>
#include <tlm>
#include <tlm_utils/simple_initiator_socket.h>
#include <tlm_utils/simple_target_socket.h>

#include "mem/mem_protocol.h"

namespace rtusim::testing {

struct Requester : sc_core::sc_module {
  struct Req {
    uint64_t at_ps, addr;
    uint32_t bytes = 8;
  };
  tlm_utils::simple_initiator_socket<Requester> socket;
  std::vector<Req> reqs;
  std::vector<tlm::tlm_generic_payload> payloads;
  std::vector<uint64_t> done_ps;  // 0 = no answer yet
  // A target that answers later (the DRAM): every request must be accepted (TLM_UPDATED,
  // END_REQ), never completed at once.
  bool expect_accepted = false;
  // Sends each request this long before its time, with the rest as the annotated delay (runs
  // ahead of the kernel, as the traversal unit does).
  uint64_t run_ahead_ps = 0;

  SC_HAS_PROCESS(Requester);
  Requester(const sc_core::sc_module_name& n, std::vector<Req> r)
      : sc_module(n), socket("socket"), reqs(std::move(r)), payloads(reqs.size()),
        done_ps(reqs.size(), 0) {
    socket.register_nb_transport_bw(this, &Requester::bw);
    SC_THREAD(run);
  }
  void run() {
    for (size_t i = 0; i < reqs.size(); ++i) {
      const uint64_t send_ps = reqs[i].at_ps - std::min(reqs[i].at_ps, run_ahead_ps);
      if (send_ps > now_ps()) wait(ps(send_ps - now_ps()));
      init_read(payloads[i], reqs[i].addr, reqs[i].bytes);
      tlm::tlm_phase ph = tlm::BEGIN_REQ;
      sc_core::sc_time d = ps(reqs[i].at_ps - now_ps());
      const tlm::tlm_sync_enum status = socket->nb_transport_fw(payloads[i], ph, d);
      if (expect_accepted) {
        EXPECT_EQ(status, tlm::TLM_UPDATED);
        EXPECT_EQ(ph, tlm::END_REQ);
      }
      if (status == tlm::TLM_COMPLETED) {
        EXPECT_EQ(payloads[i].get_response_status(), tlm::TLM_OK_RESPONSE);
        done_ps[i] = now_ps() + d.value();
      }
    }
  }
  tlm::tlm_sync_enum bw(tlm::tlm_generic_payload& t, tlm::tlm_phase& ph, sc_core::sc_time& d) {
    EXPECT_EQ(ph, tlm::BEGIN_RESP);
    done_ps[&t - payloads.data()] = now_ps() + d.value();
    return tlm::TLM_COMPLETED;
  }
};

// Answers every read latency_ps after it arrives. `deferred` = false: at once (TLM_COMPLETED
// with the delay annotated); true: accepts (END_REQ) and decides half-way through (like the DRAM,
// before the completion): a process sends BEGIN_RESP then with the rest as delay, so the
// initiator learns the time only then. Its horizon is the next such decision.
struct FixedLatencyMemory : sc_core::sc_module, MemoryHorizon {
  tlm_utils::simple_target_socket<FixedLatencyMemory> socket;
  uint64_t latency_ps;
  bool deferred;
  struct Arrival {
    uint64_t addr, at_ps;
    uint32_t bytes;
  };
  std::vector<Arrival> arrivals;
  std::vector<std::pair<uint64_t, tlm::tlm_generic_payload*>> due;  // (time, payload)
  sc_core::sc_event wake;

  SC_HAS_PROCESS(FixedLatencyMemory);
  FixedLatencyMemory(const sc_core::sc_module_name& n, uint64_t latency, bool defer)
      : sc_module(n), socket("socket"), latency_ps(latency), deferred(defer) {
    socket.register_nb_transport_fw(this, &FixedLatencyMemory::fw);
    SC_METHOD(answer);
    sensitive << wake;
    dont_initialize();
  }
  tlm::tlm_sync_enum fw(tlm::tlm_generic_payload& t, tlm::tlm_phase& ph, sc_core::sc_time& d) {
    if (ph != tlm::BEGIN_REQ) return tlm::TLM_COMPLETED;
    const uint64_t at = now_ps() + d.value();
    arrivals.push_back({t.get_address(), at, t.get_data_length()});
    if (!deferred) {
      t.set_response_status(tlm::TLM_OK_RESPONSE);
      d += ps(latency_ps);
      return tlm::TLM_COMPLETED;
    }
    due.push_back({at + latency_ps / 2, &t});
    wake.notify(ps(at + latency_ps / 2 - now_ps()));
    ph = tlm::END_REQ;
    return tlm::TLM_UPDATED;
  }
  void answer() {
    const uint64_t now = now_ps();
    uint64_t next = ~uint64_t{0};
    for (size_t i = 0; i < due.size();) {
      if (due[i].first <= now) {
        tlm::tlm_generic_payload* t = due[i].second;
        due.erase(due.begin() + static_cast<long>(i));
        t->set_response_status(tlm::TLM_OK_RESPONSE);
        tlm::tlm_phase ph = tlm::BEGIN_RESP;
        sc_core::sc_time d = ps(latency_ps - latency_ps / 2);
        socket->nb_transport_bw(*t, ph, d);
      } else {
        next = std::min(next, due[i].first);
        ++i;
      }
    }
    if (next != ~uint64_t{0}) wake.notify(ps(next - now));
  }
  uint64_t horizon_ps() const override {
    uint64_t h = kNever;
    for (const auto& d : due) h = std::min(h, d.first);
    return h;
  }
};

}  // namespace rtusim::testing
