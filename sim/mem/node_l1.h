// The node L1 seam of the cycle tier: what CycleBackend needs from its node L1, whichever model
// implements it (l1.model): "cpp", the C++ L1Cache (mem/l1_cache.h), or "rtl", the Verilated
// l1_cache.sv behind an adapter (rtl_model/rtl_l1_adapter.h).
//
// The RTL model lives in the rtusim_rtl_l1 library (Verilator), which rtusim_core must not
// depend on. So the core holds only this interface and a one-slot registry: rtusim_rtl_l1
// registers its maker when it is linked (a static registrar the library forces into every
// binary that links it), and make_node_l1("rtl", ...) in a binary without it is an InputError.
#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include <tlm>

namespace rtusim {

class MemoryHorizon;
class Stats;
struct L1Params;

class NodeL1 {
 public:
  virtual ~NodeL1() = default;

  virtual tlm::tlm_target_socket<>& upstream() = 0;       // from the unit
  virtual tlm::tlm_initiator_socket<>& downstream() = 0;  // to DRAM

  virtual uint64_t hits() const = 0;
  virtual uint64_t primary_misses() const = 0;
  virtual uint64_t merged_misses() const = 0;
  uint64_t accesses() const { return hits() + primary_misses() + merged_misses(); }
  uint64_t misses() const { return primary_misses() + merged_misses(); }
  virtual uint64_t mshr_stall_cycles() const = 0;
  virtual double mean_miss_latency_cycles() const = 0;
  virtual uint64_t bytes_from_dram() const = 0;

  // Writes `prefix`.{accesses,hits,misses,primary_misses,merged_misses,mshr_stall_cycles,
  // mean_miss_latency_cycles}, from the counters above: the same keys for every model.
  void write_stats(Stats& stats, const std::string& prefix) const;

  // Bounds the unit's run-ahead: the first time the model may act on its own (the RTL's next
  // edge, the C++ L1's next undecided lookup); nullptr: never.
  virtual const MemoryHorizon* horizon() const { return nullptr; }
  // The downstream memory's next decision, for a model that must know which fills may still
  // come (the C++ L1); ignored by one that runs on its own clock.
  virtual void set_downstream_horizon(const MemoryHorizon*) {}
  // The run succeeded: files the model writes (the RTL's VCD) go into place. Without this call
  // they are dropped.
  virtual void finish() {}
};

// Builds the RTL node L1 (SystemC module `name`, parameters `p`); `vcd_path` non-empty: a VCD of
// its signals.
using RtlNodeL1Maker = std::unique_ptr<NodeL1> (*)(const char* name, const L1Params& p,
                                                   const std::string& vcd_path);

// Called once by rtusim_rtl_l1's registrar.
void register_rtl_node_l1(RtlNodeL1Maker make);
// Whether this binary links the RTL node L1.
bool rtl_node_l1_linked();

// `model` "cpp": an L1Cache; "rtl": the registered RTL model (InputError when none is linked).
// `vcd_path` applies to the RTL model only.
std::unique_ptr<NodeL1> make_node_l1(const std::string& model, const char* name,
                                     const L1Params& p, const std::string& vcd_path);

}  // namespace rtusim
