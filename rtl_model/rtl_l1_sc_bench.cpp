// SystemC bench of the Verilated RTL L1 (default build: 8192 B, 4-way, 64 B, lru, 8 MSHRs), in
// the Verilator examples' shape: drives a few requests through a fixed-latency memory, keeps the
// requests waiting on each MSHR as the rtl tier's adapter does, checks the outcomes and the
// cycle counts of the node L1 timing spec (rtl_model/README.md), prints PASS/FAIL and sets the
// exit code. Usage: rtl_l1_sc_bench [--trace FILE.vcd]
#include <cstdio>
#include <cstring>
#include <deque>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <systemc>

#include "rtl_l1_sc.h"

using namespace rtusim;

namespace {

constexpr uint64_t kMemLatencyCycles = 10;

enum class Outcome { kHit, kPrimary, kMerged };

struct Response {
  uint64_t edge;
  uint32_t id;
  Outcome outcome;
};

SC_MODULE(Bench) {
  sc_core::sc_in<bool> clk;
  RtlL1Signals& s;
  int failures = 0;
  uint64_t edge = 0, mem_requests = 0;
  std::deque<std::pair<uint64_t, uint64_t>> fills;  // (edge the fill is driven at, address)
  std::deque<Response> responses;
  std::map<uint32_t, Outcome> outcomes;               // by id, at acceptance
  std::map<uint32_t, std::vector<uint32_t>> waiters;  // by MSHR

  SC_HAS_PROCESS(Bench);
  Bench(sc_core::sc_module_name n, RtlL1Signals& signals) : sc_module(n), s(signals) {
    SC_THREAD(run);
    sensitive << clk.pos();
  }

  void check(bool ok, const char* what) {
    if (!ok) {
      std::printf("FAIL: %s\n", what);
      ++failures;
    }
  }

  // One clock edge: sample the signals of the cycle it ends (a thread woken by the edge reads
  // the values from before it), then drive the memory side for the next cycle. Returns whether
  // a request offered in the ended cycle was accepted.
  bool tick() {
    wait();
    ++edge;
    const bool accepted = s.i_req_valid.read() && s.o_req_ready.read();
    if (accepted) {
      const uint32_t id = s.i_req_id.read();
      const Outcome o = s.o_req_hit.read()      ? Outcome::kHit
                        : s.o_req_merged.read() ? Outcome::kMerged
                                                : Outcome::kPrimary;
      outcomes[id] = o;
      if (o != Outcome::kHit) waiters[s.o_req_mshr.read()].push_back(id);
    }
    if (s.i_mem_resp_valid.read()) {  // the fill's MSHR is free from this edge: its waiters
      check(s.o_fill_valid.read(), "the fill matches a waiting MSHR");
      for (const uint32_t id : waiters[s.o_fill_mshr.read()])
        responses.push_back({edge, id, outcomes[id]});
      waiters[s.o_fill_mshr.read()].clear();
    }
    if (s.o_resp_valid.read() && s.i_resp_ready.read())
      responses.push_back({edge, s.o_resp_id.read(), Outcome::kHit});
    if (s.o_mem_req_valid.read() && s.i_mem_req_ready.read()) {
      ++mem_requests;  // filled in the cycle that ends L edges later
      fills.emplace_back(edge + kMemLatencyCycles - 1, s.o_mem_req_addr.read());
    }
    s.i_mem_resp_valid.write(false);
    if (!fills.empty() && fills.front().first == edge) {
      s.i_mem_resp_valid.write(true);
      s.i_mem_resp_addr.write(fills.front().second);
      fills.pop_front();
    }
    return accepted;
  }

  // Offers one request until accepted; returns the edge that accepted it.
  uint64_t request(uint64_t addr, uint32_t id) {
    s.i_req_valid.write(true);
    s.i_req_addr.write(addr);
    s.i_req_id.write(id);
    while (!tick()) {
    }
    s.i_req_valid.write(false);
    return edge;
  }

  Response await(uint32_t id) {
    for (int i = 0; i < 1000; ++i) {
      for (auto it = responses.begin(); it != responses.end(); ++it)
        if (it->id == id) {
          const Response r = *it;
          responses.erase(it);
          return r;
        }
      tick();
    }
    check(false, "response timeout");
    return {};
  }

  void run() {
    s.rst_n.write(false);
    s.i_resp_ready.write(true);
    s.i_mem_req_ready.write(true);
    wait();
    wait();
    s.rst_n.write(true);
    wait();

    // A miss, looked up in cycle a-1: its line read is taken at edge a+1 = (a-1) + 2, and it
    // is answered at its fill's edge, L edges later.
    const uint64_t a0 = request(0x1000, 1);
    const Response r1 = await(1);
    check(r1.outcome == Outcome::kPrimary, "first access is a primary miss");
    check(r1.edge == a0 + 1 + kMemLatencyCycles, "answered at the fill, L + 2 after the lookup");
    check(mem_requests == 1, "one memory request for the miss");

    // A hit: answered at (a-1) + 2.
    const uint64_t a1 = request(0x1008, 2);
    const Response r2 = await(2);
    check(r2.outcome == Outcome::kHit, "second access to the line hits");
    check(r2.edge == a1 + RtlL1Fixed::kHitLatencyCycles, "hit answered 2 cycles after lookup");

    // Two requests to one missing line: one memory request, the second merged, both answered
    // at the fill.
    request(0x2000, 3);
    request(0x2010, 4);
    const Response r3 = await(3), r4 = await(4);
    check(r3.outcome == Outcome::kPrimary, "primary miss");
    check(r4.outcome == Outcome::kMerged, "secondary miss is merged");
    check(r4.edge == r3.edge, "merged request answered at the primary's fill");
    check(mem_requests == 2, "merged miss sent no memory request");

    std::printf("%s: rtl_l1_sc_bench (%d failure%s)\n", failures ? "FAIL" : "PASS", failures,
                failures == 1 ? "" : "s");
    sc_core::sc_stop();
  }
};

}  // namespace

int sc_main(int argc, char** argv) {
  std::string vcd;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--trace") == 0 && i + 1 < argc) {
      vcd = argv[++i];
    } else {
      std::fprintf(stderr, "usage: rtl_l1_sc_bench [--trace FILE.vcd]\n");
      return 2;
    }
  }
  sc_core::sc_clock clk("clk", 1, sc_core::SC_NS);
  RtlL1Signals s;
  auto l1 = make_rtl_l1("l1", CacheParams{}, clk, s);
  Bench bench("bench", s);
  bench.clk(clk);

  sc_core::sc_start(sc_core::SC_ZERO_TIME);
  if (!vcd.empty() && !open_rtl_l1_vcd(*l1, vcd)) {
    std::fprintf(stderr, "rtl_l1_sc_bench: --trace needs a build with -DRTUSIM_RTL_TRACE=ON\n");
    return 2;
  }
  sc_core::sc_start();
  close_rtl_l1_vcd();
  return bench.failures == 0 ? 0 : 1;
}
