// A cycle-level C++ driver of one Verilated (non-SystemC) l1_cache.sv build, behind a small
// interface so tests can loop over every built parameter combination. Signal meanings and
// timing: the header comment of rtl_model/l1_cache.sv.
#pragma once
#include <cstdint>
#include <memory>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "rtl/rtl_l1_registry.h"

namespace rtusim {
// gtest prints a build parameter as its model name.
inline void PrintTo(const RtlL1Build& b, std::ostream* os) { *os << b.model; }
}  // namespace rtusim

namespace rtusim::rtltest {

struct Inputs {
  bool rst_n = true;
  bool req_valid = false;
  uint64_t req_addr = 0;
  uint32_t req_id = 0;
  bool resp_ready = true;
  bool mem_req_ready = true;
  bool mem_resp_valid = false;
  uint64_t mem_resp_addr = 0;
};

struct Outputs {
  bool req_ready = false;
  bool req_hit = false, req_merged = false;  // the lookup's outcome (primary: both false)
  uint32_t req_mshr = 0;
  bool resp_valid = false;
  uint32_t resp_id = 0;
  bool mem_req_valid = false;
  uint64_t mem_req_addr = 0;
  bool fill_valid = false;
  uint32_t fill_mshr = 0;
  uint32_t mshrs_busy = 0;
};

enum class Outcome : uint8_t { kHit, kPrimaryMiss, kMergedMiss };

class RtlL1Model {
 public:
  virtual ~RtlL1Model() = default;
  // Drives the inputs for the current cycle and settles the combinational outputs (clk low).
  virtual void drive(const Inputs& in) = 0;
  virtual Outputs outputs() const = 0;
  // One rising edge (then clk low again, outputs settled with the inputs last driven).
  virtual void posedge() = 0;
  // Holds rst_n low for two edges, then releases it with every input idle.
  virtual void reset() = 0;

  // Blocking mode: one request at a time; a hit's response is taken together with the next
  // request's acceptance; a miss's line read is taken the cycle after its lookup and its fill
  // driven the cycle after that. Appends each access's outcome (from the lookup outputs).
  // Throws std::runtime_error on a protocol violation (not ready, no or wrong hit response, no
  // line read for a miss, a fill that frees another MSHR than the miss's).
  virtual void replay_blocking(std::span<const uint64_t> addrs, std::vector<Outcome>& out) = 0;

  virtual uint64_t cycles() const = 0;
  virtual uint64_t memory_requests() const = 0;
  // Starts a VCD of every RTL signal (false when not built with -DRTUSIM_RTL_TRACE=ON).
  virtual bool open_vcd(const std::string& path) = 0;
};

// Names of the built models ("Vc" + stem, e.g. "Vcl1_8192_4_64_lru"), RTUSIM_RTL_L1_BUILDS order.
const std::vector<std::string>& cpp_model_names();
// A fresh, reset model of the build whose registry model name is `registry_model`
// ("Vl1_8192_4_64_lru"); nullptr when none.
std::unique_ptr<RtlL1Model> make_cpp_model(const std::string& registry_model);

}  // namespace rtusim::rtltest
