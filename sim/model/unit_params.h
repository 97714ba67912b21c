// Parameters of the traversal unit, and the config keys they come from (declared in
// unit_params.cpp): sim.rays_in_flight, sim.step_cycles, sim.stack_depth, isect.lanes,
// isect.latency_cycles, isect.interval_cycles. Plain data: no SystemC.
#pragma once
#include <cstdint>

namespace rtusim {

class ConfigReader;

struct UnitParams {
  uint32_t rays_in_flight = 32;
  uint64_t clock_period_ps = 1000;
  uint32_t step_cycles = 4;       // node arrival -> step decided
  uint32_t stack_depth = 32;      // hardware stack entries per ray (steps deeper are counted)
  uint32_t isect_lanes = 1;
  uint32_t isect_latency_cycles = 20;
  uint32_t isect_interval_cycles = 1;  // initiation interval per lane
  uint32_t node_line_bytes = 64;  // node fetches are split at node L1 lines
  uint32_t data_line_bytes = 64;  // list/triangle fetches: data cache lines or DRAM bursts
};

// Throws KeyError naming the config key of a bad value.
void validate(const UnitParams& p);

// Reads the keys above (clock and line sizes are derived later, by CycleParams::derive()).
UnitParams read_unit_params(ConfigReader& r);

}  // namespace rtusim
