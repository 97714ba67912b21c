// The RTL node L1 as a SystemC module: the Verilated l1_cache.sv for one built parameter
// combination (rtl/rtl_l1_registry.h), bound to a bundle of signals named after its ports.
// Port semantics and timing: the header comment of rtl_model/l1_cache.sv.
#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include <systemc>

#include "cache/cache_params.h"

namespace rtusim {

// One signal per port of l1_cache (the clock is supplied separately). Widths as Verilator maps
// them: 1 bit -> bool, 2..32 -> uint32_t, 33..64 -> uint64_t (ADDR_W = 48, ID_W = 16, MSHR
// indices 3 bits).
// Inputs accept writes from more than one process: the node L1 adapter (rtl_l1_adapter.h)
// drives a request or a fill from the TLM call that brings it when it joins the cycle already
// being driven (SystemC's processes run one at a time: the last write of a delta wins).
template <class T>
using RtlL1Input = sc_core::sc_signal<T, sc_core::SC_UNCHECKED_WRITERS>;

struct RtlL1Signals {
  RtlL1Input<bool> rst_n{"rst_n"};
  RtlL1Input<bool> i_req_valid{"i_req_valid"};
  sc_core::sc_signal<bool> o_req_ready{"o_req_ready"};
  RtlL1Input<uint64_t> i_req_addr{"i_req_addr"};
  RtlL1Input<uint32_t> i_req_id{"i_req_id"};
  sc_core::sc_signal<bool> o_req_hit{"o_req_hit"}, o_req_merged{"o_req_merged"};
  sc_core::sc_signal<uint32_t> o_req_mshr{"o_req_mshr"};
  sc_core::sc_signal<bool> o_resp_valid{"o_resp_valid"};
  RtlL1Input<bool> i_resp_ready{"i_resp_ready"};
  sc_core::sc_signal<uint32_t> o_resp_id{"o_resp_id"};
  sc_core::sc_signal<bool> o_mem_req_valid{"o_mem_req_valid"};
  RtlL1Input<bool> i_mem_req_ready{"i_mem_req_ready"};
  sc_core::sc_signal<uint64_t> o_mem_req_addr{"o_mem_req_addr"};
  RtlL1Input<bool> i_mem_resp_valid{"i_mem_resp_valid"};
  RtlL1Input<uint64_t> i_mem_resp_addr{"i_mem_resp_addr"};
  sc_core::sc_signal<bool> o_fill_valid{"o_fill_valid"};
  sc_core::sc_signal<uint32_t> o_fill_mshr{"o_fill_mshr"};
  sc_core::sc_signal<uint32_t> o_mshrs_busy{"o_mshrs_busy"};
};

// Fixed RTL parameters of every build (l1_cache.sv defaults).
struct RtlL1Fixed {
  static constexpr uint32_t kAddrBits = 48;
  static constexpr uint32_t kIdBits = 16;
  static constexpr uint32_t kMshrs = 8;
  static constexpr uint32_t kHitLatencyCycles = 1;
};

// The Verilated module for `p` (size, assoc, line, policy), named `name`, its ports bound to
// `clk` and `s`. Throws InputError (rtl_l1_build) when the combination is not built.
std::unique_ptr<sc_core::sc_module> make_rtl_l1(const char* name, const CacheParams& p,
                                                sc_core::sc_signal_in_if<bool>& clk,
                                                RtlL1Signals& s);

// Starts a VCD of `module` (one made by make_rtl_l1) into `path`; call after
// sc_start(SC_ZERO_TIME). False when the build has no tracing (-DRTUSIM_RTL_TRACE=ON).
bool open_rtl_l1_vcd(sc_core::sc_module& module, const std::string& path);
// Flushes and closes the VCD, if any.
void close_rtl_l1_vcd();

}  // namespace rtusim
