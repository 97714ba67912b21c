#include "model/cycle_params.h"

#include <cmath>

#include "cache/cache_config.h"
#include "rtl/rtl_l1_registry.h"
#include "util/error.h"

namespace rtusim {

void CycleParams::finish() {
  if (!(clock_mhz > 0)) throw InputError("sim.clock_mhz: must be positive");
  const uint64_t period = static_cast<uint64_t>(std::llround(1e6 / clock_mhz));
  unit.clock_period_ps = node_l1.clock_period_ps = period;
  unit.node_line_bytes = node_l1.cache.line_bytes;
  if (data_cache) {
    data_cache->clock_period_ps = period;
    unit.data_line_bytes = data_cache->cache.line_bytes;
    validate(*data_cache, "dcache");
  } else {
    unit.data_line_bytes = dram.burst_bytes();
  }
  validate(unit);
  validate(node_l1, "l1");
  if (node_l1_model == "rtl") {
    rtl_l1_build(node_l1.cache);  // InputError naming an unbuilt combination
    if (node_l1.mshrs != RtlL1Build::kMshrs)
      throw InputError("l1.model = rtl: no RTL build for l1.mshrs=" +
                       std::to_string(node_l1.mshrs) + " (every RTL build has " +
                       std::to_string(RtlL1Build::kMshrs) + " MSHRs; built: " +
                       rtl_l1_builds_text() + ", as size/assoc/line/policy)");
    if (node_l1.hit_cycles != RtlL1Build::kHitCycles)
      throw InputError("l1.hit_cycles: l1.model = rtl answers a hit " +
                       std::to_string(RtlL1Build::kHitCycles) +
                       " cycles after the request (acceptance edge + HIT_LATENCY 1); set " +
                       std::to_string(RtlL1Build::kHitCycles) + " or use l1.model = cpp");
  } else if (node_l1_model != "cpp") {
    throw InputError("l1.model: must be cpp or rtl, not " + node_l1_model);
  }
  validate(dram, "dram");
}

CycleParams read_cycle_params(ConfigReader& r) {
  CycleParams p;
  auto u32 = [&](const std::string& key, uint32_t fallback, int64_t min, int64_t max) {
    return static_cast<uint32_t>(r.get_int(key, fallback, min, max));
  };
  p.clock_mhz = r.get_float("sim.clock_mhz", 1000.0, 1.0, 100000.0);
  p.unit.rays_in_flight = u32("sim.rays_in_flight", p.unit.rays_in_flight, 1, 1 << 20);
  p.unit.step_cycles = u32("sim.step_cycles", p.unit.step_cycles, 0, 1 << 20);
  p.unit.stack_depth = u32("sim.stack_depth", p.unit.stack_depth, 1, TraversalState::kStackDepth);
  p.unit.isect_lanes = u32("isect.lanes", p.unit.isect_lanes, 1, 1024);
  p.unit.isect_latency_cycles = u32("isect.latency_cycles", p.unit.isect_latency_cycles, 0, 1 << 20);
  p.unit.isect_interval_cycles = u32("isect.interval_cycles", p.unit.isect_interval_cycles, 1, 1 << 20);

  const FetchCacheParams caches = read_fetch_cache_params(r);
  p.node_l1.cache = caches.node_l1;
  p.node_l1.hit_cycles = u32("l1.hit_cycles", p.node_l1.hit_cycles, 1, 1 << 20);
  p.node_l1.mshrs = u32("l1.mshrs", p.node_l1.mshrs, 1, 4096);
  p.node_l1_model = r.get_string("l1.model", p.node_l1_model, {"cpp", "rtl"});
  p.vcd_path = r.get_string("sim.vcd", "");
  L1Params dcache;
  dcache.hit_cycles = u32("dcache.hit_cycles", dcache.hit_cycles, 1, 1 << 20);
  dcache.mshrs = u32("dcache.mshrs", dcache.mshrs, 1, 4096);
  if (caches.data_cache) {
    dcache.cache = *caches.data_cache;
    p.data_cache = dcache;
  }

  const std::string standard =
      r.get_string("dram.standard", "DDR4-2400", known_dram_standards());
  const DramParams d = dram_preset(standard);
  p.dram = d;
  p.dram.channels = u32("dram.channels", d.channels, 1, 64);
  p.dram.banks = u32("dram.banks", d.banks, 1, 1024);
  p.dram.row_bytes = static_cast<uint64_t>(
      r.get_int("dram.row_bytes", static_cast<int64_t>(d.row_bytes), 1, int64_t{1} << 30));
  p.dram.data_rate_mts = u32("dram.data_rate_mts", d.data_rate_mts, 1, 100000);
  p.dram.bus_bytes = u32("dram.bus_bytes", d.bus_bytes, 1, 1024);
  p.dram.burst_length = u32("dram.burst_length", d.burst_length, 1, 1024);
  p.dram.tRCD_ns = r.get_float("dram.tRCD_ns", d.tRCD_ns, 0.0, 1e6);
  p.dram.tRP_ns = r.get_float("dram.tRP_ns", d.tRP_ns, 0.0, 1e6);
  p.dram.tCL_ns = r.get_float("dram.tCL_ns", d.tCL_ns, 0.0, 1e6);
  try {
    p.finish();
  } catch (const InputError& e) {
    throw InputError(r.origin() + ": " + e.what());
  }
  return p;
}

}  // namespace rtusim
