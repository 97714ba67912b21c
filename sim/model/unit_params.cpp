// The traversal unit's keys and their validation.
#include "model/unit_params.h"

#include <string>

#include "config/param.h"
#include "model/event_wheel.h"
#include "traversal/traversal.h"
#include "util/error.h"

namespace rtusim {
namespace {

const UnitParams kDefaults;
const IntParam kRaysInFlight("sim.rays_in_flight", kDefaults.rays_in_flight, 1, 1 << 20, "rays",
                             "rays the unit holds at once");
const IntParam kStepCycles("sim.step_cycles", kDefaults.step_cycles, 0, 1 << 20, "cycles",
                           "node data in to traversal step decided");
const IntParam kStackDepth("sim.stack_depth", kDefaults.stack_depth, 1,
                           TraversalState::kStackDepth, "entries",
                           "hardware stack per ray; deeper steps counted in "
                           "unit.stack_overflow_steps");
const IntParam kIsectLanes("isect.lanes", kDefaults.isect_lanes, 1, 1024, "",
                           "ray-triangle test pipelines");
const IntParam kIsectLatency("isect.latency_cycles", kDefaults.isect_latency_cycles, 0, 1 << 20,
                             "cycles", "triangle test issue to result");
const IntParam kIsectInterval("isect.interval_cycles", kDefaults.isect_interval_cycles, 1,
                              1 << 20, "cycles", "initiation interval of a test lane");

}  // namespace

void validate(const UnitParams& p) {
  auto at_least_1 = [](uint64_t v, const char* key) {
    if (v == 0) throw KeyError(key, "must be at least 1");
  };
  at_least_1(p.rays_in_flight, "sim.rays_in_flight");
  at_least_1(p.clock_period_ps, "sim.clock_mhz");
  at_least_1(p.stack_depth, "sim.stack_depth");
  at_least_1(p.isect_lanes, "isect.lanes");
  at_least_1(p.isect_interval_cycles, "isect.interval_cycles");
  at_least_1(p.node_line_bytes, "l1.line");
  at_least_1(p.data_line_bytes, "dcache.line");
  constexpr uint32_t kMaxSlots = 1u << EventWheel::kSlotBits;  // 1048576
  if (p.rays_in_flight > kMaxSlots)
    throw KeyError("sim.rays_in_flight", std::to_string(p.rays_in_flight) + " is more than " +
                                             std::to_string(kMaxSlots));
  if (p.stack_depth > TraversalState::kStackDepth)
    throw KeyError("sim.stack_depth", std::to_string(p.stack_depth) + " is more than " +
                                          std::to_string(TraversalState::kStackDepth) + " entries");
}

UnitParams read_unit_params(ConfigReader& r) {
  UnitParams p;
  auto u32 = [&](const IntParam& k) { return static_cast<uint32_t>(k.read(r)); };
  p.rays_in_flight = u32(kRaysInFlight);
  p.step_cycles = u32(kStepCycles);
  p.stack_depth = u32(kStackDepth);
  p.isect_lanes = u32(kIsectLanes);
  p.isect_latency_cycles = u32(kIsectLatency);
  p.isect_interval_cycles = u32(kIsectInterval);
  return p;
}

}  // namespace rtusim
