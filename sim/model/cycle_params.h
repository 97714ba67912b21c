// Parameters of the cycle tier and the config keys they come from.
//
// Keys (default):
//   sim.rays_in_flight        32        rays the unit holds at once (contract key)
//   sim.clock_mhz             1000      unit and cache clock
//   sim.step_cycles           4         node data in -> traversal step decided
//   sim.stack_depth           32        hardware stack entries per ray (<= 64); steps that go
//                                       deeper are counted in unit.stack_overflow_steps
//   isect.lanes               1         ray-triangle test pipelines
//   isect.latency_cycles      20        test issue -> result
//   isect.interval_cycles     1         initiation interval of a lane
//   l1.hit_cycles             2         node L1 hit latency (geometry: l1.size/assoc/line/policy)
//   l1.mshrs                  8         node L1 outstanding line misses
//   l1.model                  "cpp"     node L1 model: cpp (mem/l1_cache.h) | rtl (the Verilated
//                                       rtl_model/l1_cache.sv; only built size/assoc/line/policy
//                                       combinations, l1.mshrs = 8, l1.hit_cycles = 2)
//   sim.vcd                   ""        l1.model = rtl: write a VCD of the RTL L1's signals here
//   dcache.enable             false     list/triangle cache (else straight to DRAM, per burst)
//   dcache.hit_cycles         2         (geometry: dcache.size/assoc/line/policy)
//   dcache.mshrs              8
//   dram.standard             "DDR4-2400"  preset for the keys below: DDR4-2400 | DDR4-3200
//   dram.channels             1
//   dram.banks                16        per channel
//   dram.row_bytes            8192      row buffer per channel
//   dram.data_rate_mts        2400      (3200)
//   dram.bus_bytes            8         data bus width per channel
//   dram.burst_length         8
//   dram.tRCD_ns, dram.tRP_ns, dram.tCL_ns   14.16 each (13.75 for DDR4-3200)
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "config/config_reader.h"
#include "mem/dram/dram_params.h"
#include "mem/l1_cache.h"
#include "model/traversal_unit.h"

namespace rtusim {

struct CycleParams {
  double clock_mhz = 1000.0;
  UnitParams unit;                   // clock_period_ps and line sizes derived
  L1Params node_l1;                  // clock_period_ps derived
  std::optional<L1Params> data_cache;  // nullopt: lists and triangles straight to DRAM
  DramParams dram;
  std::string node_l1_model = "cpp";  // "cpp" | "rtl" (sim.tier = rtl sets "rtl")
  std::string vcd_path;  // sim.vcd: with the C++ L1 the unit's state, with the RTL L1 its
                         // signals; empty: none

  // Derives the clock period and the unit's request split from the rest; validates everything.
  void finish();
};

// Reads the keys above (and l1.* / dcache.* geometry through read_fetch_cache_params).
// Throws InputError naming the key.
CycleParams read_cycle_params(ConfigReader& r);

}  // namespace rtusim
