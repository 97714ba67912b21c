#include "mem/dram/dram_params.h"

#include <cmath>

#include "util/error.h"

namespace rtusim {

namespace {
uint64_t ns_to_ps(double ns) { return static_cast<uint64_t>(std::llround(ns * 1000.0)); }
}  // namespace

uint64_t DramParams::burst_ps() const {
  return static_cast<uint64_t>(std::llround(burst_length * 1e6 / data_rate_mts));
}
uint64_t DramParams::tRCD_ps() const { return ns_to_ps(tRCD_ns); }
uint64_t DramParams::tRP_ps() const { return ns_to_ps(tRP_ns); }
uint64_t DramParams::tCL_ps() const { return ns_to_ps(tCL_ns); }

const std::vector<std::string>& known_dram_standards() {
  static const std::vector<std::string> names = {"DDR4-2400", "DDR4-3200"};
  return names;
}

DramParams dram_preset(const std::string& standard) {
  DramParams p;  // DDR4-2400 17-17-17 (Micron MT40A -083, JEDEC DDR4-2400T)
  if (standard == "DDR4-2400") return p;
  if (standard == "DDR4-3200") {
    // JEDEC DDR4-3200AA 22-22-22 (Micron MT40A -062E): tCK = 0.625 ns, 22 x 0.625 = 13.75 ns.
    p.standard = standard;
    p.data_rate_mts = 3200;
    p.tRCD_ns = p.tRP_ns = p.tCL_ns = 13.75;
    return p;
  }
  throw InputError("dram.standard: unknown standard '" + standard + "'");
}

void validate(const DramParams& p, const std::string& prefix) {
  auto fail = [&](const std::string& key, const std::string& what) {
    throw InputError(prefix + "." + key + ": " + what);
  };
  if (p.channels == 0) fail("channels", "must be at least 1");
  if (p.banks == 0) fail("banks", "must be at least 1");
  if (p.row_bytes < p.burst_bytes() || p.row_bytes % p.burst_bytes() != 0)
    fail("row_bytes", std::to_string(p.row_bytes) + " is not a multiple of a burst (" +
                          std::to_string(p.burst_bytes()) + " bytes)");
  if (p.data_rate_mts == 0) fail("data_rate_mts", "must be positive");
  if (p.bus_bytes == 0) fail("bus_bytes", "must be positive");
  if (p.burst_length == 0) fail("burst_length", "must be positive");
  if (!(p.tRCD_ns >= 0) || !(p.tRP_ns >= 0) || !(p.tCL_ns >= 0))
    fail("tRCD_ns", "timings must be non-negative");
}

}  // namespace rtusim
