#include "model/cycle_params.h"

#include <cmath>

#include "config/param.h"
#include "rtl/rtl_l1_registry.h"
#include "util/error.h"

namespace rtusim {
namespace {

const FloatParam kClockMhz("sim.clock_mhz", CycleParams{}.clock_mhz, 1.0, 100000.0, "MHz",
                           "unit and cache clock (cycle and rtl tiers)");
const StringParam kVcd("sim.vcd", "", {}, "path",
                       "cycle and rtl tiers: write a VCD here, the unit's state (l1.model = "
                       "cpp) or the RTL L1's signals (rtl); \"\" = none");

}  // namespace

void CycleParams::derive() {
  const uint64_t period = clock_mhz > 0 ? static_cast<uint64_t>(std::llround(1e6 / clock_mhz)) : 0;
  unit.clock_period_ps = node_l1.clock_period_ps = period;
  unit.node_line_bytes = node_l1.cache.line_bytes;
  if (data_cache) {
    data_cache->clock_period_ps = period;
    unit.data_line_bytes = data_cache->cache.line_bytes;
  } else {
    unit.data_line_bytes = dram.burst_bytes();
  }
}

void CycleParams::finish() {
  derive();
  validate(*this);
}

void validate(const CycleParams& p) {
  if (!(p.clock_mhz > 0)) throw KeyError("sim.clock_mhz", "must be positive");
  validate(p.unit);
  validate_timing(p.node_l1, "l1");
  if (p.data_cache) validate_timing(*p.data_cache, "dcache");
  if (p.node_l1_model == "rtl") {
    try {
      rtl_l1_build(p.node_l1.cache);  // InputError naming an unbuilt combination
    } catch (const InputError& e) {
      throw KeyError({"l1.model", "l1.size", "l1.assoc", "l1.line", "l1.policy"}, e);
    }
    if (p.node_l1.mshrs != RtlL1Build::kMshrs)
      throw KeyError({"l1.mshrs", "l1.model"},
                     "l1.model = rtl: no RTL build for l1.mshrs=" + std::to_string(p.node_l1.mshrs) +
                         " (every RTL build has " + std::to_string(RtlL1Build::kMshrs) +
                         " MSHRs; built: " + rtl_l1_builds_text() + ", as size/assoc/line/policy)");
    if (p.node_l1.hit_cycles != RtlL1Build::kHitCycles)
      throw KeyError({"l1.hit_cycles", "l1.model"},
                     "l1.model = rtl answers a hit " + std::to_string(RtlL1Build::kHitCycles) +
                         " cycles after the request (acceptance edge + HIT_LATENCY 1); set " +
                         std::to_string(RtlL1Build::kHitCycles) + " or use l1.model = cpp");
  } else if (p.node_l1_model != "cpp") {
    throw KeyError("l1.model", "must be cpp or rtl, not " + p.node_l1_model);
  }
}

double read_clock_mhz(ConfigReader& r) { return kClockMhz.read(r); }
std::string read_vcd_path(ConfigReader& r) { return kVcd.read(r); }

CycleParams make_cycle_params(double clock_mhz, const UnitParams& unit, const L1Config& l1,
                              const L1Config& dcache, const DramParams& dram,
                              const std::string& vcd_path) {
  CycleParams p;
  p.clock_mhz = clock_mhz;
  p.unit = unit;
  p.node_l1 = l1.params;
  p.node_l1_model = l1.model;
  if (dcache.enable) p.data_cache = dcache.params;
  p.dram = dram;
  p.vcd_path = vcd_path;
  p.derive();
  return p;
}

CycleParams read_cycle_params(ConfigReader& r) {
  const double clock_mhz = read_clock_mhz(r);
  const UnitParams unit = read_unit_params(r);
  const L1Config l1 = read_node_l1_config(r);
  const std::string vcd = read_vcd_path(r);
  const L1Config dcache = read_dcache_config(r);
  const DramParams dram = read_dram_params(r);
  CycleParams p = make_cycle_params(clock_mhz, unit, l1, dcache, dram, vcd);
  try {
    validate(p);
  } catch (const KeyError& e) {
    r.fail(e);
  }
  return p;
}

}  // namespace rtusim
