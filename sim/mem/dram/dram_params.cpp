#include "mem/dram/dram_params.h"

#include <cmath>

#include "config/param.h"
#include "mem/dram/dram_backends.h"
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
uint64_t DramParams::latency_ps() const { return ns_to_ps(latency_ns); }

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
    p.latency_ns = p.tRCD_ns + p.tCL_ns;
    return p;
  }
  throw KeyError("dram.standard", "unknown standard '" + standard + "'");
}

void validate(const DramParams& p, const std::string& prefix) {
  auto fail = [&](const std::string& key, const std::string& what) {
    throw KeyError(prefix + "." + key, what);
  };
  if (!DramBackends::contains(p.backend))
    fail("backend", "unknown backend '" + p.backend + "' (known: " + DramBackends::names_text() + ")");
  if (p.channels == 0) fail("channels", "must be at least 1");
  if (p.banks == 0) fail("banks", "must be at least 1");
  if (p.bus_bytes == 0) fail("bus_bytes", "must be positive");
  if (p.burst_length == 0) fail("burst_length", "must be positive");
  if (p.row_bytes < p.burst_bytes() || p.row_bytes % p.burst_bytes() != 0)
    throw KeyError({prefix + ".bus_bytes", prefix + ".burst_length", prefix + ".row_bytes"},
                   std::to_string(p.bus_bytes) + " x " + prefix + ".burst_length " +
                       std::to_string(p.burst_length) + " = " + std::to_string(p.burst_bytes()) +
                       " bytes per burst does not divide " + prefix + ".row_bytes = " +
                       std::to_string(p.row_bytes));
  if (p.data_rate_mts == 0) fail("data_rate_mts", "must be positive");
  if (!(p.tRCD_ns >= 0) || !(p.tRP_ns >= 0) || !(p.tCL_ns >= 0))
    fail("tRCD_ns", "timings must be non-negative");
  if (!(p.latency_ns >= 0)) fail("latency_ns", "must be non-negative");
}

namespace {

const DramParams kDefaults;
const StringParam kBackend("dram.backend", kDefaults.backend, DramBackends::names(), "",
                           "DRAM timing model: " + DramBackends::summaries_text());
const StringParam kStandard("dram.standard", kDefaults.standard, known_dram_standards(), "",
                            "speed-grade preset: the default of dram.data_rate_mts, "
                            "tRCD_ns, tRP_ns, tCL_ns and latency_ns");
const IntParam kChannels("dram.channels", kDefaults.channels, 1, 64, "", "channels");
const IntParam kBanks("dram.banks", kDefaults.banks, 1, 1024, "", "banks per channel");
const IntParam kRowBytes("dram.row_bytes", static_cast<int64_t>(kDefaults.row_bytes), 1,
                         int64_t{1} << 30, "bytes", "row buffer (page) per channel");
const IntParam kDataRate("dram.data_rate_mts", kDefaults.data_rate_mts, 1, 100000, "MT/s",
                         "transfers per second (preset: 2400 or 3200)");
const IntParam kBusBytes("dram.bus_bytes", kDefaults.bus_bytes, 1, 1024, "bytes",
                         "data bus width per channel");
const IntParam kBurstLength("dram.burst_length", kDefaults.burst_length, 1, 1024, "transfers",
                            "transfers per burst");
const FloatParam kTrcd("dram.tRCD_ns", kDefaults.tRCD_ns, 0.0, 1e6, "ns",
                       "ACT to column command (preset: 14.16 or 13.75)");
const FloatParam kTrp("dram.tRP_ns", kDefaults.tRP_ns, 0.0, 1e6, "ns",
                      "PRE to ACT (preset: 14.16 or 13.75)");
const FloatParam kTcl("dram.tCL_ns", kDefaults.tCL_ns, 0.0, 1e6, "ns",
                      "column read to first data (preset: 14.16 or 13.75)");
const FloatParam kLatency("dram.latency_ns", kDefaults.latency_ns, 0.0, 1e6, "ns",
                          "backend fixed: request to first data (default: a row miss, "
                          "dram.tRCD_ns + dram.tCL_ns)");

}  // namespace

DramParams read_dram_params(ConfigReader& r) {
  const std::string backend = kBackend.read(r);
  const DramParams d = dram_preset(kStandard.read(r));
  DramParams p = d;
  p.backend = backend;
  auto u32 = [&](const IntParam& k, uint32_t fallback) {
    return static_cast<uint32_t>(k.read(r, fallback));
  };
  p.channels = u32(kChannels, d.channels);
  p.banks = u32(kBanks, d.banks);
  p.row_bytes = static_cast<uint64_t>(kRowBytes.read(r, static_cast<int64_t>(d.row_bytes)));
  p.data_rate_mts = u32(kDataRate, d.data_rate_mts);
  p.bus_bytes = u32(kBusBytes, d.bus_bytes);
  p.burst_length = u32(kBurstLength, d.burst_length);
  p.tRCD_ns = kTrcd.read(r, d.tRCD_ns);
  p.tRP_ns = kTrp.read(r, d.tRP_ns);
  p.tCL_ns = kTcl.read(r, d.tCL_ns);
  // A row miss of the timings in effect (the preset's, or the config's own tRCD/tCL).
  p.latency_ns = kLatency.read(r, p.tRCD_ns + p.tCL_ns);
  try {
    validate(p, "dram");
  } catch (const KeyError& e) {
    r.fail(e);
  }
  return p;
}

}  // namespace rtusim
