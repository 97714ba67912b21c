// Parameters of the cycle tier, assembled from the config subtrees it uses (sim.clock_mhz,
// sim.vcd declared in cycle_params.cpp; unit_params.h, l1_params.h, dram_params.h for the rest).
// Plain data: no SystemC.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "mem/dram/dram_params.h"
#include "mem/l1_params.h"
#include "model/unit_params.h"

namespace rtusim {

class ConfigReader;

struct CycleParams {
  double clock_mhz = 1000.0;
  UnitParams unit;                   // clock_period_ps and line sizes derived
  L1Params node_l1;                  // clock_period_ps derived
  std::optional<L1Params> data_cache;  // nullopt: lists and triangles straight to DRAM
  DramParams dram;
  std::string node_l1_model = "cpp";  // "cpp" | "rtl" (sim.tier = rtl sets "rtl")
  std::string vcd_path;  // sim.vcd: with the C++ L1 the unit's state, with the RTL L1 its
                         // signals; empty: none

  // Derives the clock period and the unit's request split from the rest.
  void derive();
  // derive(), then validate(*this).
  void finish();
};

// The checks across keys (clock, unit, L1 timing, the RTL L1's builds); the cache geometry and
// the DRAM are checked when read (and by their modules on construction). Throws KeyError naming
// the keys involved.
void validate(const CycleParams& p);

// The cycle tier's own keys.
double read_clock_mhz(ConfigReader& r);
std::string read_vcd_path(ConfigReader& r);

// Assembles derived (not validated) cycle params from the configured subtrees.
CycleParams make_cycle_params(double clock_mhz, const UnitParams& unit, const L1Config& l1,
                              const L1Config& dcache, const DramParams& dram,
                              const std::string& vcd_path);

// Reads every key above and validates (errors name the key and where it was set).
CycleParams read_cycle_params(ConfigReader& r);

}  // namespace rtusim
