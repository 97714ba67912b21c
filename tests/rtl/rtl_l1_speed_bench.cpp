// Accesses per second of the Verilated RTL L1 (C++ model, blocking mode: one access at a time,
// fill returned at once) against SetAssocCache on the same node trace in the same run; median
// of several runs. Usage: rtl_l1_speed_bench [RUNS]  (trace: the kitchen when
// $RTUSIM_SCENES/kitchen/kitchen.gltf exists, else the built-in Cornell room)
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench_timing.h"
#include "cache/set_assoc_cache.h"
#include "rtl/rtl_l1_registry.h"
#include "rtl_l1_harness.h"
#include "rtl_l1_traces.h"

using namespace rtusim;
using namespace rtusim::rtltest;
using rtusim::bench_timing::median;
using rtusim::bench_timing::now_s;

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  const std::vector<uint64_t>* kitchen = kitchen_node_trace();
  const std::vector<uint64_t>& trace = kitchen ? *kitchen : cornell_node_trace();
  std::printf("trace: %s, %zu node fetches; median of %d runs\n",
              kitchen ? "kitchen 128x128 primary" : "cornell 128x128 primary", trace.size(),
              runs);
  std::printf("%-22s %10s %12s %12s %12s %9s\n", "build", "misses", "rtl_acc/s", "rtl_cyc/s",
              "cpp_acc/s", "cpp/rtl");
  for (const RtlL1Build& b : rtl_l1_builds()) {
    const CacheParams p = b.cache();
    std::vector<double> rtl_rate, rtl_cycles, cpp_rate;
    uint64_t rtl_misses = 0, cpp_misses = 0;
    for (int r = 0; r < runs; ++r) {
      auto m = make_cpp_model(std::string(b.model));
      std::vector<Outcome> out;
      const double t0 = now_s();
      m->replay_blocking(trace, out);
      const double t1 = now_s();
      rtl_rate.push_back(trace.size() / (t1 - t0));
      rtl_cycles.push_back(m->cycles() / (t1 - t0));
      rtl_misses = m->memory_requests();

      SetAssocCache c(p);
      const double t2 = now_s();
      uint64_t misses = 0;
      for (const uint64_t a : trace) misses += c.access(a) ? 0 : 1;
      const double t3 = now_s();
      cpp_rate.push_back(trace.size() / (t3 - t2));
      cpp_misses = misses;
    }
    std::printf("%-22.*s %10llu %12.3g %12.3g %12.3g %9.0f%s\n", static_cast<int>(b.model.size()),
                b.model.data(), static_cast<unsigned long long>(rtl_misses), median(rtl_rate),
                median(rtl_cycles), median(cpp_rate), median(cpp_rate) / median(rtl_rate),
                rtl_misses == cpp_misses ? "" : "  MISMATCH");
  }
  return 0;
}
