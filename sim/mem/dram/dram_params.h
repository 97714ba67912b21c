// Parameters of the DRAM timing model: geometry, timings and the address mapping.
//
// Defaults: DDR4-2400 17-17-17 (JEDEC speed bin DDR4-2400T; Micron MT40A1G8 8Gb x8 data sheet,
// speed grade -083: tCK = 0.833 ns, CL = 17, tRCD = tRP = 14.16 ns), one 64-bit channel of eight
// x8 devices: 16 banks (4 bank groups x 4), an 8 KB row (1 KB page per device x 8), burst length
// 8 (64 bytes per burst, BL/2 = 4 clocks = 3.333 ns on the bus).
//
// Address mapping (most to least significant): row : bank : channel : column, with
//   column  = addr mod row_bytes
//   channel = (addr / row_bytes) mod channels
//   bank    = (addr / (row_bytes * channels)) mod banks
//   row     = addr / (row_bytes * channels * banks)
// so one row-sized chunk of the image stays in one row, and consecutive chunks spread over the
// channels, then the banks.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace rtusim {

struct DramParams {
  std::string backend = "fr-fcfs";     // timing model: see dram_backends.h
  std::string standard = "DDR4-2400";  // preset the timings below came from
  uint32_t channels = 1;
  uint32_t banks = 16;          // per channel (one rank)
  uint64_t row_bytes = 8192;    // row buffer (page) per channel
  uint32_t data_rate_mts = 2400;  // transfers per second (MT/s); tCK = 2000 / rate ns
  uint32_t bus_bytes = 8;       // data bus width per channel
  uint32_t burst_length = 8;    // transfers per burst
  double tRCD_ns = 14.16;       // ACT -> column command
  double tRP_ns = 14.16;        // PRE -> ACT
  double tCL_ns = 14.16;        // column read -> first data
  double latency_ns = 28.32;    // backend "fixed": request -> first data (a row miss: tRCD + tCL)

  uint32_t burst_bytes() const { return bus_bytes * burst_length; }
  // Bus time of one burst, in picoseconds (rounded).
  uint64_t burst_ps() const;
  uint64_t tRCD_ps() const;
  uint64_t tRP_ps() const;
  uint64_t tCL_ps() const;
  uint64_t latency_ps() const;
};

// Names accepted by dram_preset().
const std::vector<std::string>& known_dram_standards();
// The timings and geometry of a named speed grade ("DDR4-2400", "DDR4-3200").
DramParams dram_preset(const std::string& standard);
// Throws KeyError naming the key (`prefix` + ".channels", ...) on an inconsistent value.
void validate(const DramParams& p, const std::string& prefix);

class ConfigReader;
// Reads the dram.* keys (declared in dram_params.cpp: the preset first, then each value) and
// validates them; errors name the key and the `--set` or file line.
DramParams read_dram_params(ConfigReader& r);

}  // namespace rtusim
