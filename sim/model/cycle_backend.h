// The cycle tier behind the tracer's TraceBackend seam: a SystemC top of host interface,
// traversal unit, node L1 (C++ or, with l1.model = rtl, the Verilated RTL), optional list/triangle cache and DRAM, simulated batch by batch.
// Time and counters accumulate across batches.
//
// SystemC elaborates once per simulation context: each CycleBackend builds its top in a context
// of its own, so a process may run several backends one after another (one per layout, one per
// regress case); trace() runs sc_start in that context until the batch is done.
#pragma once
#include <memory>
#include <span>

#include "layout/memory_image.h"
#include "model/cycle_params.h"
#include "tracer/trace_backend.h"

namespace sc_core {
class sc_simcontext;
}

namespace rtusim {

class Stats;
class VcdWriter;
class L1Cache;
class NodeL1;
class Dram;
class TraversalUnit;

class CycleBackend final : public TraceBackend {
 public:
  // `image` must outlive the backend. `params` come validated (read_cycle_params(), or
  // CycleParams::finish()); the clock period and line sizes are derived here. The modules
  // check their own params on construction (InputError).
  CycleBackend(const MemoryImage& image, const CycleParams& params);
  ~CycleBackend() override;

  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override;

  uint64_t cycles() const;  // simulated so far
  uint64_t rays() const { return rays_; }
  const NodeL1& node_l1() const;  // L1Cache, or the RTL adapter with l1.model = rtl
  const L1Cache* data_cache() const;  // nullptr when lists and triangles go straight to DRAM
  const Dram& dram() const;
  const TraversalUnit& unit() const;

  // sim.cycles, sim.rays_per_second, dram.bytes.{nodes,lists,triangles,total},
  // dram.gbytes_per_second, dram.row_hit_rate (and row hits/misses/conflicts, requests),
  // l1.{accesses,hits,misses,primary_misses,merged_misses,mshr_stall_cycles,
  // mean_miss_latency_cycles}, dcache.* likewise when on, unit.utilisation (steps per cycle),
  // unit.* counters, traversal.node_fetches.
  void write_stats(Stats& stats) const;

  // Completes the outputs of a run that went well (the unit's VCD, when sim.vcd asks for it).
  void finish();

 private:
  struct Top;
  void make_current() const;  // this backend's context becomes SystemC's current one

  CycleParams params_;
  sc_core::sc_simcontext* context_;  // owned; declared before top_, destroyed after it
  std::unique_ptr<Top> top_;
  std::unique_ptr<VcdWriter> vcd_;  // the unit's state, with the C++ node L1
  uint64_t rays_ = 0;
};

}  // namespace rtusim
